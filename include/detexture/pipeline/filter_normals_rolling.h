// Structure recovery (Sun et al. 2019, Sec. 5, Eq. 3): rolling iterations of
// a joint bilateral filter of the *input* normals n_j, guided by G^k:
//
//   n^{k+1}_i = (1/W^k_i) Σ_{j} w(p_i, p_j, σs) · w_r(G^k_i, G^k_j, σr) · n_j
//
// starting from n¹ of the Gaussian filter (Eq. 1). Because the input normals
// are filtered afresh every iteration, structures larger than σs that the
// Gaussian blurred come back step by step while texture stays smoothed.
//
// Choices where the paper is silent:
// - Range kernel: w_r = exp(-|G_i - G_j|² / (2 s²)) with s = 2 sin(σr/2), the
//   chord of the angle σr. For small angles this is exp(-θ²/(2σr²)) in the
//   angle θ between the guidance normals, so σr reads in degrees as in the
//   paper's Table 2, and it needs no acos per pair.
// - The sum runs over the sub-neighborhood Ω_i by default, like Eq. 1, so
//   texture normals never re-enter; the paper's R_i is kept as an option
//   (use_subneighborhood = false). Points with an empty Ω_i use R_i. Ω_i's
//   membership weights ω_j multiply the terms, as in Eq. 1.
// - Iterations: at most `iterations`, stopping early once the mean change of
//   the normals between two iterations falls below `tolerance_deg`.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/pipeline/guidance_normals.h"
#include "detexture/types.h"

namespace detexture {

struct FilterNormalsRollingParams {
  /// σs: spatial scale, in the cloud's units; > 0 (the same σs as Eq. 1).
  double sigma_s = 0.0;
  /// σr: range scale, in degrees, in (0, 180]. Larger gives smoother results.
  /// At 30° this filter alone brings back creases of 90° and more (75°
  /// partly); at 45° it leaves creases of 75-105° blurred, and remove_texture
  /// keeps them by the surface split (drop_neighbors_across_surfaces.h). The
  /// paper's Table 2 uses 30-45°; 45° was measured on both quality suites
  /// against 30° (bench/RESULTS.md, row sigma-r-30): normal error −2 to −6%
  /// on the curved and thin real shapes (the limbs' rounded parts are
  /// smoothed, not split into facets), the cubes' and the pyramid's edges
  /// within 0.5%.
  double sigma_r_deg = 45.0;
  /// Rolling iterations k (after the Gaussian step), ≥ 0.
  int iterations = 10;
  /// Stop when the mean normal change of an iteration is below this, in degrees, ≥ 0.
  double tolerance_deg = 0.1;
  /// Sum over Ω_i (true, our default) or over R_i as Eq. 3 is printed (false).
  bool use_subneighborhood = true;
  GuidanceNormalsParams guidance;
};

struct RollingFilterResult {
  Normals normals;               ///< #P by 3 unit normals N^k
  int iterations = 0;            ///< iterations run
  double last_change_deg = 0.0;  ///< mean normal change of the last iteration
};

/// Eq. 3 iterated. `input` are the input normals n_j, `initial` the Gaussian
/// result n¹ (by value: pass it with std::move when it is not needed after,
/// and its memory is reused); `omega` (#P, ω_j in [0, 1]) may be empty when
/// use_subneighborhood is false.
/// `progress` receives the fraction of the iteration budget used.
RollingFilterResult filter_normals_rolling(const Positions& P, const Normals& input,
                                           Normals initial, const Neighborhoods& R,
                                           const std::vector<float>& omega,
                                           const FilterNormalsRollingParams& params,
                                           const ProgressFn& progress = {});

void validate(const FilterNormalsRollingParams& params);

}  // namespace detexture
