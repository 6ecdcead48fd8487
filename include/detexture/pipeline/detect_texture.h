// Texture identification (Sun et al. 2019, Sec. 4, Eq. 2).
//
// A RANSAC plane is fitted to every radius neighborhood R_i. Point p_j is
// counted as an inlier T_j times over the N_j neighborhoods that produced a
// plane and contain it; it is underlying surface iff T_j > δ·N_j (Eq. 2),
// texture otherwise. The non-texture points of R_i form the sub-neighborhood
// Ω_i used by the Gaussian filter (Eq. 1).
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct DetectTextureParams {
  /// λ: RANSAC distance threshold, in the cloud's units; > 0. A point farther
  /// than λ from a neighborhood's plane is an outlier of that plane. Smaller
  /// than the texture's height, larger than noise and than the sag r²/(2·R) of
  /// the underlying surface over a neighborhood of radius r.
  double lambda = 0.0;
  /// δ: fraction of a point's neighborhoods in which it must be an inlier to
  /// count as underlying surface, in (0, 1). Larger marks more points texture.
  double delta = 0.8;
  /// Probability that the best plane of a neighborhood has been found when
  /// RANSAC stops early, in (0, 1).
  double confidence = 0.99;
  /// Cap on RANSAC tries per neighborhood, ≥ 1.
  int max_iterations = 100;
  /// Refit the best plane to its inliers by least squares before the final
  /// inlier count (not in the paper; steadier classification).
  bool refine = true;
  /// Seed of the per-point generators (seeded from seed and point index).
  std::uint64_t seed = 1;
};

struct TextureDetection {
  std::vector<std::uint8_t> is_texture;  ///< #P; 1 = texture (Eq. 2 fails), 0 = underlying surface
  std::vector<std::uint32_t> inliers;    ///< #P; T_i
  std::vector<std::uint32_t> members;    ///< #P; N_i, neighborhoods with a plane that contain i
  std::size_t texture_points = 0;
  std::size_t no_plane = 0;      ///< neighborhoods with fewer than 3 points or collinear
  double mean_iterations = 0.0;  ///< RANSAC tries per neighborhood
};

/// Classify every point as texture or underlying surface (Eq. 2). Deterministic
/// for any thread count. Throws std::invalid_argument on out-of-range params.
TextureDetection detect_texture(const Positions& P, const Neighborhoods& R,
                                const DetectTextureParams& params, const ProgressFn& progress = {});

/// Check params; throws std::invalid_argument with a sentence naming the bad one.
void validate(const DetectTextureParams& params);

}  // namespace detexture
