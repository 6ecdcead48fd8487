// Error of a result point cloud against a ground-truth sample of the surface
// it should recover: the paper's Table 3 metrics (Sec. 6: Dmax, Dmean, σ)
// plus the signed offset, normal errors and coverage.
//
// The distance of a result point r is point-to-plane at its nearest
// ground-truth sample g (with unit normal n_g): the signed distance
// (r - g).n_g and its absolute value. With a dense ground truth this is the
// distance to the surface up to O(spacing^2 * curvature), where point-to-point
// distances would be biased by the sample spacing.
#pragma once

#include <cstddef>
#include <string>

#include "detexture/types.h"

namespace detexture {

struct GroundTruthComparison {
  std::size_t result_points = 0;
  std::size_t ground_truth_points = 0;
  double diagonal =
      0.0;  ///< bounding-box diagonal of the ground truth, the unit of the *_relative values

  // Unsigned point-to-plane distances |(r - g).n_g|, result -> ground truth.
  double max_distance = 0.0;   ///< Dmax
  double mean_distance = 0.0;  ///< Dmean
  double std_distance = 0.0;   ///< σ, population standard deviation (divides by #R)

  // Signed distances (r - g).n_g, positive outside (along n_g). The mean is a
  // uniform shift of the whole result; the standard deviation is texture (or
  // noise) left in it.
  double mean_signed_distance = 0.0;
  double std_signed_distance = 0.0;

  // Normal errors: the angle between the result normal and n_g, in degrees
  // in [0, 180]. Orientation counts: a flipped normal is 180 degrees off.
  // Result points whose normal is zero are left out and counted.
  bool has_normals = false;  ///< false when the result has no normals: the next three are 0
  double mean_angle_degrees = 0.0;
  double within_10_degrees_percent = 0.0;  ///< share of normals at most 10 degrees off, in %
  std::size_t zero_normals = 0;

  // Coverage, ground truth -> result: the distance from each ground-truth
  // sample to the nearest result point (point-to-point). Large values show
  // holes; a mean much above the result's own spacing shows clustering.
  double mean_coverage_distance = 0.0;
  double max_coverage_distance = 0.0;
};

/// Compare result positions R (#R by 3) and normals RN (#R by 3, or 0 rows
/// when the result has none) with ground-truth positions G (#G by 3) and unit
/// normals GN (#G by 3). Throws std::invalid_argument when R or G is empty,
/// when GN does not have #G rows, or when RN has neither 0 nor #R rows.
GroundTruthComparison compare_to_ground_truth(const Positions& R, const Normals& RN,
                                              const Positions& G, const Normals& GN);

/// The comparison as a JSON object with stable keys (docs/synth_and_compare.md):
/// result_points, ground_truth_points, diagonal, dmax, dmean, dstd,
/// dmax_relative, dmean_relative, dstd_relative, signed_mean, signed_std,
/// signed_mean_relative, signed_std_relative, normal_angle_mean_degrees,
/// normals_within_10_degrees_percent (both null without normals), zero_normals,
/// coverage_mean, coverage_max, coverage_mean_relative, coverage_max_relative.
std::string comparison_to_json(const GroundTruthComparison& c);

/// The comparison as an aligned, human-readable table (one metric a line).
std::string comparison_to_table(const GroundTruthComparison& c);

}  // namespace detexture
