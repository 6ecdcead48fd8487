// Output normals that describe the output surface (after Sec. 6): the normal
// of each updated point is the plane that best fits its updated neighbors,
// weighted in space and guided by the filtered normals.
//
//   C_i = Σ_{j∈R_i, |p'_j - p'_i| <= ρ} w_ij (p'_j - c_i)(p'_j - c_i)ᵀ,
//   w_ij = exp(-|p'_j - p'_i|²/(2σ²)) · exp(-(1 - n_i·n_j)²/(2σr²)),
//   c_i  = Σ w_ij p'_j / Σ w_ij,
//
// where p' are the updated positions and n the filtered normals (Eq. 3's
// result); the output normal is C_i's eigenvector of the smallest eigenvalue,
// signed like n_i.
//
// Why: the paper outputs the filtered normals n, which are smoothed at σs
// (= r by default). The position update fits them only where the texture
// was; the surface points stay where they were (anchors, update_positions.h),
// so the output surface keeps its facets and curvature at a finer scale than
// n shows. The range weight keeps the fit on one side of a crease: neighbors
// whose filtered normal turns away by more than about 45° weigh little. The
// mesh mode does the same with the output's faces (face_normals.h).
//
// The fit alone helps only where the output positions are better than n:
// measured on both quality suites (bench/quality_real_notes.md), the mean
// normal error drops by 8-40% on smooth and faceted shapes with sparse
// features (the person 6.09° → 5.30°, the duck 3.29° → 2.55°, the blob
// 1.70° → 1.06°, the sphere 1.06° → 0.65°), but where dense waves or grooves
// stay partly in the positions the fit follows them (the torus with waves
// 3.89° → 8.50°, the noisy U grooves 3.64° → 6.19°, the knot 3.60° → 4.95°).
// Gates on a point's own texture label, height or fit roughness kept part of
// both. What does separate them is the disagreement around the point: where
// waves or noise stay in the positions, the fit swings about n from point to
// point, by 3-5° on average over a neighborhood; where the positions are
// clean it differs from n by under 1° (a smoothed curve, a facet). So the
// output is blended (blend_low_deg, blend_high_deg; the default): with ā_i
// the mean angle between the fit and n over p_i and its neighbors within ρ
// whose fit was computed (a fit refused for turning past max_turn_deg counts
// as 180°),
//
//   w_i = clamp((high - ā_i) / (high - low), 0, 1),   n'_i ∝ w_i fit_i + (1 - w_i) n_i.
//
// The window 1-2° was measured against 1-3° and 0.5-2.5° (bench/RESULTS.md):
// wider windows won more on the real shapes and lost up to 3.5% on the noisy
// U grooves.
//
// The isotropic path (session 12). ā alone tells waves from facets poorly:
// on the person, the duck, the blob, the fit beats n at any ā up to 3°,
// because their positions hold facets and features smaller than σs, not
// waves. What differs is the direction of the departures fit_j − n_j over
// the point and its neighbors within ρ: across waves or grooves left in the
// positions they lie along one direction (the share κ of the largest
// eigenvalue of their scatter's trace: 0.93-0.95, median, on the suites'
// waves and grooves), on facets and small features they spread over the
// tangent plane (0.60-0.76 on the organic cases). So where κ is under
// blend_coherence (0.9; ramping to 0 at 0.95) the fit is also taken up to
// ā = blend_isotropic_high_deg (3.5°; ramping from 2.5°), the larger of the
// two weights winning. Measured on both suites and on 30 unseen cases
// (bench/quality_real_notes.md, session 12): normal error −11% on the noisy
// ellipsoid and the blob, −5% on the person, the duck and the noisy cube;
// +2.3% on the knot's waves, +1.8% on the pyramid's V grooves; lower on 29
// of the 30 unseen cases. Fit and blend take about 5% of a run (bench/speed's 150k
// sphere: 0.06 s of 1.29 s).
//
// Waves left in the positions (session 14). The blend keeps n where waves
// or grooves stayed in the positions, but the positions keep them. The
// same statistics flag those points for remove_texture, which then runs
// the position update again with their anchors lowered (remove_texture.h,
// wave_share_low): a point is flagged when ā_i >= waves_min_deg, κ_i >=
// waves_coherence, and the departures vary linearly across the
// neighborhood: with e the direction of the largest eigenvalue, the squared
// correlation between (p'_j − p'_i)·e and (fit_j − n_j)·e over the same
// points is at least waves_linearity. Within ρ a neighborhood sees less
// than a period of the waves left, and across a crest or a trough the
// departure changes sign steadily (the squared correlation's median is
// 0.73-0.80 over the points of the suites' waves and grooves that pass the
// ā and κ tests); over the facets and small features of organic shapes it
// scatters (0.29-0.33 on the person, the spider and the duck). Rounded
// edges that the filtered normals smooth pass all three tests too, which
// is why remove_texture gates its second pass on the share of flagged
// points (remove_texture.h, wave_share_low). Measured on both suites and
// 30 unseen cases (bench/quality_real_notes.md, session 14).
//
// The open window (session 15). The blend guards against waves left, and
// costs elsewhere: where the positions keep none, the fit beats the blended
// normal even at ā over 2° (the filtered normals round the shape's own
// curvature at σs). So the result also holds the blend with a window opened
// to blend_open_low_deg - blend_open_high_deg (5-10°; the fit alone does
// as well on average but follows a lone bump left in the positions), which
// remove_texture takes on clouds where few points are flagged as waves
// (remove_texture.h, blend_share_low).
//
// The fine scale (session 17). One σ (0.3 r) rounds what is smaller than
// it: facets of a low-poly model, seams, the rims of thin parts; σ/2
// follows them but also follows the noise left in the positions (σ = 0.15 r
// everywhere: the person 5.03° → 4.93°, the noisy cube +19%). So each point
// also gets a plane fit with weights of σ · fine_ratio, and takes it where
// it departs from the fit at σ by more than its own noise explains, in the
// spirit of the intersection-of-confidence-intervals rule for choosing a
// scale per point. The scatter off each fit's plane is λ0 = σn² + c λ1 at
// both scales (noise, plus the shape's bending, which grows with the
// window's spread λ1), which gives σn² per point; averaged over p_i and its
// fitted neighbors within ρ, it gives the fine fit's noise angle
// θ = √(σn² / (λ1 N)) (N the weights' effective count, (Σw)²/Σw²). With d
// the angle between the two fits, the fine one weighs
// clamp(d/θ − fine_gamma, 0, 1). Measured on both suites and 60 unseen
// cases (bench/quality_real_notes.md, session 17): the person 5.03° → 4.94°
// (under its input's 4.97°), the duck −2.4%, the spider −1.6%; the disc
// +3.3%, the multiscale sphere +2.4% (smooth clean shapes, where the bending
// looks like no noise and the fine fit follows small remnants); the unseen
// cases −0.6%.
//
// The range normals (session 18). The range weight above reads n, which
// the filters round at σs: across a facet's edge, a seam or the rim of a
// thin part, n turns gradually, so neighbors on the other side weigh
// nearly as much, and the fit leans across. Normals that describe the input
// surface itself (those that came with it: a mesh's, a scanner's) turn
// where the surface does. So the range weight can read other normals m
// (remove_texture passes the input normals when the input had them,
// RemoveTextureParams::fit_range_input_normals): w_ij's second factor
// becomes exp(-(1 - m_i·m_j)²/(2σr²)), pairs where m_i or m_j is zero
// keeping n's. Everything else (the turn limit, the sign, the blend) still
// reads n. Measured on both suites and 60 unseen cases
// (bench/quality_real_notes.md, session 18).
//
// A fit is not taken, and n_i kept (and counted), when fewer than 3
// neighbors weigh in, when the fit is degenerate (collinear neighbors, see
// kMinSpreadRatio), or when it turns more than max_turn_deg from n_i (a part
// thinner than the fit window, where the plane has no meaning).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct FitNormalsToPositionsParams {
  /// σ: spatial scale of the fit's weights, in the cloud's units; > 0.
  /// RemoveTextureParams fills it from its fit_sigma (0.3 r).
  double sigma = 0.0;
  /// ρ: neighbors of R_i farther than this (in the updated positions) are
  /// left out; > 0. RemoveTextureParams fills it with the solve radius (0.5 r).
  double radius = 0.0;
  /// σr: range scale on 1 - n_i·n_j of the filtered normals (or of the
  /// range normals m, see above); > 0.
  /// 0.3 weighs a neighbor turned by 30° at 0.9, by 60° at 0.25, by 90° at 0.004.
  double range_sigma = 0.3;
  /// A fit that turns farther than this from the filtered normal is not
  /// taken, degrees in (0, 180].
  double max_turn_deg = 45.0;
  /// The fine scale: a second fit at σ · fine_ratio, taken where it departs
  /// from the fit at σ by more than fine_gamma times its own expected noise
  /// (see above); in [0, 1), 0 turns it off.
  double fine_ratio = 0.5;
  /// The fine scale's confidence factor Γ: the fine fit is taken from a
  /// departure of Γ times its noise angle on, fully from Γ + 1; >= 0.
  double fine_gamma = 2.0;
  /// Blend: where the fitted normals differ from the filtered ones by a mean
  /// angle of at most this over a point and its neighbors (within the
  /// fit's radius), the fit is taken; degrees in [0, blend_high_deg).
  double blend_low_deg = 1.0;
  /// Blend: from this mean angle on, the filtered normal is kept; linearly
  /// between the two. Degrees in [0, 180]; 0 takes every fit (no blend).
  double blend_high_deg = 2.0;
  /// Blend, the isotropic path: where the fit's departures from the
  /// filtered normals around a point have no one direction, the fit is also
  /// taken up to a mean angle of blend_isotropic_high_deg (see above). κ, the
  /// largest eigenvalue's share of Σ (fit − n)(fit − n)ᵀ over the point and
  /// its neighbors within ρ, is 1 for departures along one direction (across
  /// waves or grooves left in the positions) and 1/2 for departures spread
  /// over the tangent plane (facets, small features). The path is open
  /// below this κ and closed at 0.05 above it; in [0, 1), 0 turns it off.
  double blend_coherence = 0.9;
  /// Blend, the isotropic path: up to this mean angle (degrees, in [0,
  /// 180]; ramping down over the degree below it) the fit is taken where κ
  /// allows.
  double blend_isotropic_high_deg = 3.5;
  /// The open window (see above): the fit is taken up to this mean angle ā,
  /// in degrees; in [0, blend_open_high_deg).
  double blend_open_low_deg = 5.0;
  /// The open window: from this mean angle on, the filtered normal is kept;
  /// linearly between the two. Degrees in (0, 180].
  double blend_open_high_deg = 10.0;
  /// Waves left (see above): the least mean angle ā, in degrees, of a
  /// flagged point; in [0, 180], 0 flags nothing. Needs the blend
  /// (blend_high_deg > 0).
  double waves_min_deg = 2.0;
  /// Waves left: the least κ of a flagged point, in [0, 1].
  double waves_coherence = 0.9;
  /// Waves left: the least squared correlation of the departures with the
  /// position across the neighborhood, in [0, 1].
  double waves_linearity = 0.7;
};

struct FitNormalsToPositionsResult {
  Normals normals;       ///< #P by 3 unit normals
  std::size_t kept = 0;  ///< points that kept the filtered normal (see above)
  /// Points whose output is the filtered normal, or partly, because the fit
  /// disagrees with it around them (the blend; 0 without it).
  std::size_t blended = 0;
  /// #P: 1 where waves or grooves look left in the positions (see above);
  /// empty when waves_min_deg or blend_high_deg is 0.
  std::vector<std::uint8_t> waves;
  /// #P by 3: the blend with the open window (blend_open_low_deg,
  /// blend_open_high_deg) in place of blend_low_deg and blend_high_deg, and
  /// no isotropic path; empty without the blend (blend_high_deg 0).
  /// remove_texture takes it on clouds where few points flag waves
  /// (remove_texture.h, blend_share_low).
  Normals open;
  /// Points whose open output is the filtered normal, or partly.
  std::size_t open_blended = 0;
};

void validate(const FitNormalsToPositionsParams& params);

/// P  #P by 3 updated positions p'
/// normals  #P by 3 filtered unit normals n (zero rows are kept as they are)
/// R  neighborhoods of the points (any radius; entries beyond ρ are skipped)
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
FitNormalsToPositionsResult fit_normals_to_positions(const Positions& P, const Normals& normals,
                                                     const Neighborhoods& R,
                                                     const FitNormalsToPositionsParams& params);

/// The same with the range weights read from range_normals (see "The range
/// normals" above).
/// range_normals  #P by 3 unit normals m, signed like n (zero rows: n's weight)
FitNormalsToPositionsResult fit_normals_to_positions(const Positions& P, const Normals& normals,
                                                     const Normals& range_normals,
                                                     const Neighborhoods& R,
                                                     const FitNormalsToPositionsParams& params);

}  // namespace detexture
