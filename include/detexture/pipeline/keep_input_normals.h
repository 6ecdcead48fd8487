// Output normals where the output surface is the input surface (after
// Sec. 6, session 18): where no point near p_i moved, the input normal is
// kept.
//
//   m_i = max_{j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ} |p'_j - p_j|,
//   w_i = clamp((high λ - m_i) / ((high - low) λ), 0, 1),
//   n''_i ∝ w_i ñ_i + (1 - w_i) n'_i,
//
// where p are the input positions, p' the updated ones, n' the output
// normals so far (the fit and its blend, fit_normals_to_positions.h), ñ_i
// the input normal signed like n'_i, and λ the RANSAC threshold of Eq. 2.
// Texture points (Eq. 2) keep n'_i.
//
// Why: the update holds the underlying surface where it is (anchors,
// update_positions.h), so away from the texture most of the output surface
// is the input surface itself. There its input normal, read at the input's
// own scale (given with the input, or estimated on 16 neighbors), describes
// it better than the fit to the output positions, which weighs a
// neighborhood of σ = 0.3 r and rounds the facets, seams and creases finer
// than that. The test is on movement, not on agreement with n': where noise
// is in the positions, the update smooths it and the points move, so noisy
// input normals are not kept (a tolerance of 0.5-2 λ kept them on the noisy
// cases: the noisy cube +63% in normal error, with normals estimated from
// its noisy positions given as the input's). The ramp's λ/20 - λ/5 is far
// below the relief counted as surface. Measured on both quality suites and
// 60 unseen cases (bench/quality_real_notes.md, session 18).
//
// Exact input normals (session 21): a surface point's input normal ñ_i is
// also taken, however far the points moved, where
//
//   (1/k) Σ_{j ∈ k nearest of R_i} |ñ_i·(p_j - p_i)| <= e λ   and   ∠(ñ_i, n'_i) <= θ,
//
// with k = exact_neighbors, e = exact_residual, θ = exact_angle_deg. The
// first test says the input normal is exact: its nearest neighbors lie in
// its tangent plane, as on a noise-free surface and not on a noisy one,
// where points off the plane by the noise fail it (so the noisy cases keep
// their output normals, which is why the movement test above exists). The
// second takes it only as a small correction of n': where the update rounded
// a faceted or smooth base by a fraction of λ and the fit followed, the
// input normal is the surface's, but on a wave's flank, which barely moves
// and is tilted by the wave, it is not. Measured on both quality suites and
// 60 unseen cases, normal error (bench/quality_real_notes.md, session 21):
// -7.7% on the suites (geometric mean; the plane with domes -26%, the
// multiscale sphere -20%, the cube with bumps -15%; the torus with waves
// +1.1%, the knot +0.9% the most; the noisy cases unchanged), -5.6% on 30
// unseen dense reliefs, -3.3% on 30 unseen waves and grooves (+0.6% the
// most). θ = 3 gave -7.4 / -4.4 / -2.1%, 5 with a movement bound of 2 λ
// -4.0 / -5.1 / -3.8% (the torus +1.9%); a larger θ under a movement bound
// took the waves' tilts (15° within 2 λ: the torus +14%).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct KeepInputNormalsParams {
  /// The input normal is taken fully where nothing within ρ moved by more
  /// than this, in units of λ; in [0, high).
  double low = 0.05;
  /// From this move on (units of λ) the output normal stays; linearly
  /// between the two. >= 0; 0 keeps no input normal (before session 18).
  double high = 0.2;
  /// ρ: the neighbors of R_i within this (input positions) are looked at;
  /// > 0. RemoveTextureParams fills it with the solve radius (0.5 r).
  double radius = 0.0;
  /// λ of Eq. 2, in the cloud's units; > 0. RemoveTextureParams fills it.
  double lambda = 0.0;
  /// θ: an exact input normal (below) is taken where it lies within this
  /// angle of the output normal, in degrees; in [0, 90), 0 takes none
  /// (before session 21).
  double exact_angle_deg = 4.0;
  /// e: the input normal counts as exact where its exact_neighbors nearest
  /// neighbors lie within this mean distance of its tangent plane, in units
  /// of λ; >= 0.
  double exact_residual = 0.05;
  /// k: how many nearest neighbors the exactness test reads; >= 3.
  int exact_neighbors = 8;
};

struct KeepInputNormalsResult {
  Normals normals;        ///< #P by 3 unit normals
  std::size_t kept = 0;   ///< points whose output took the input normal, fully or in part
  std::size_t exact = 0;  ///< ... of which taken fully as exact (θ, e above) and not for the move
};

void validate(const KeepInputNormalsParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// input_normals  #P by 3 input normals ñ (zero rows are not kept)
/// normals  #P by 3 output normals n' so far
/// is_texture  #P Eq. 2 labels (empty: no point is texture)
/// R  neighborhoods of P, rows sorted by distance (any radius; entries
///    beyond ρ are skipped)
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
KeepInputNormalsResult keep_input_normals(const Positions& P, const Positions& updated,
                                          const Normals& input_normals, const Normals& normals,
                                          const std::vector<std::uint8_t>& is_texture,
                                          const Neighborhoods& R,
                                          const KeepInputNormalsParams& params);

}  // namespace detexture
