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
// Texture points (Eq. 2) take no input normal by the move; since session 25
// they may by the exactness tests below, where their nearest neighbors'
// input normals agree.
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
//
// Exact input normals where the surface stayed (session 23): an exact ñ_i
// is also taken up to θ_s = still_angle_deg from n'_i where
//
//   m_i <= μ λ,   ∠(ñ_i, ñ_j) <= φ for its k nearest neighbors j,
//   ∠(ñ_i, n'_i) <= max_{j ∈ R_i, |p_j - p_i| <= ρ} ∠(n'_j, n'_i),
//
// with m_i the largest move within ρ (above), μ = still_move, φ =
// still_uniform_deg. This is for faceted bases (low-poly models subdivided
// once, where the facets are the size of r): the fit rounds each facet
// into its neighbors, by 5-20° on the thin parts, though nothing there
// moved. Each test turns away a relief the same three others pass: the move
// turns away relief the update lifted (grooves that moved); the uniform
// normals, a wave's or a scale's flank, whose normals turn from point to
// point; the cone, a wide flat V groove's wall on a flat face, which did not
// move and is as flat as a facet, but where the output normals around do not
// turn (a facet's tilt is as large as the turn of the rounded surface over
// ρ, a groove wall's is not). Measured on both quality suites, the spot
// check's 60 unseen cases and 36 more on six other assimp models
// (bench/quality_real_notes.md, session 23), normal error: -0.96% on the 30
// dense reliefs and -0.98% on the 30 waves and grooves (sydney's bumps
// -6.0%, the faerie's -5.3%), -0.30% on the 36; bench/quality +0.01% (the
// torus +0.1% the most), the real suite -0.21% (the disc -2.0%); no case
// worse by more than 0.2%, residual texture and Dmax unchanged (normals
// only). Without the uniform test the waves took their tilts (the knot
// +3.4%); without the cone, the pyramid's V grooves (+1.9%; +16 to +23%
// with a move of 2-3 λ).
//
// Facets found past their edges (session 24): both tests above read the k
// nearest neighbors as one plane, so on a faceted base whose facets are a
// few point spacings wide they fail within a spacing or two of every edge,
// most of such a facet: on the spot check's faerie, whose input normals are
// exact at 73% of the points, the output took them at 30% (44% with this
// test). ñ_i also counts as exact (both tests) where it is a flat facet's:
//
//   F_i = { j among the K nearest of R_i : ∠(ñ_j, ñ_i) <= φ },
//   |F_i| >= m,   (1/|F_i|) Σ_{j ∈ F_i} |ñ_i·(p_j - p_i)| <= e λ,
//   σ_2(F_i) >= s σ_1(F_i),   #{ j among the K : φ < ∠(ñ_j, ñ_i) <= c φ } <= t
//   (or those lie on at most g other facets: "Shallow edges" below),
//
// with K = facet_neighbors (at least k), m = facet_members (k until
// session 28), s = facet_spread, c = facet_jump, t = facet_transitional,
// σ_1 >= σ_2 the largest eigenvalues of the covariance of F_i's positions
// (σ_1 > 0), angles between normals unsigned
// (|ñ_j·ñ_i|), and neighbors without a normal counted among the K but in
// neither set. With φ = 0 no neighbor is transitional. The members of its facet lie in its tangent
// plane and spread in two directions (not a line along a cylinder's or a wave's ruling, whose
// normals also agree); and the other neighbors' normals are off by a jump, an edge's, not by a
// gradual turn, a wave's flank or a smooth surface's, where many lie just past φ. The move and cone
// tests still apply. Measured on both quality suites and 96 unseen cases, normal error
// (bench/quality_real_notes.md, session 24): -3.7% on the spot check's 30 dense reliefs (sydney's
// bumps -17%, the faerie's -10%), -1.8% on its 30 waves and grooves, -2.3% on the broad check's 36;
// bench/quality -2.9% (the plane with domes -19%; the pyramid +0.5% the most), the real suite
// -1.5%; residual texture and Dmax unchanged (normals only). Without the jump test the waves took
// their flanks (the broad torus's +0.7%); the move bound stays the largest move within ρ: with the
// own move only (or within 0.5 ρ), the faerie's bumps -18% but the axe's V grooves +15%
// (+9%), whose walls stay where the bottom moved.
//
// The reach and the facet's move (session 25): where the surface stayed,
// the cone above is replaced by
//
//   min_{j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ} ∠(n'_j, ñ_i) <= α ∠(n'_i, ñ_i),
//
// with α = still_reach: the output normals around reach towards ñ_i, not
// merely turn as much in any direction. A rounded facet's fit turns back to
// the facet's own normal towards its middle; around a groove wall the
// update filled, the output normals stay the base's, or turn with the
// base's curvature, which on a curved base (a rod, a torus, a limb) is as
// large as a shallow wall's tilt and passed the cone. And where the
// largest move within ρ exceeds μ λ, the surface also counts as stayed
// where the largest move over ñ_i's facet within ρ does not:
//
//   max_{j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ, ∠(ñ_j, ñ_i) <= φ} |p'_j - p_j| <= μ λ,
//
// for facets next to relief the update took down (the move at the relief
// is no sign that the facet beside it moved). Alone this took the walls of
// V grooves whose bottom moved and whose upper part did not (+1.3% to
// +3.4% on four unseen models); with the reach they are turned away.
// Measured on both quality suites and 96 unseen cases, normal error
// (bench/quality_real_notes.md, session 25): -2.2% on the spot check's 30
// dense reliefs, -1.8% on its 30 waves and grooves, -1.2% on the broad
// check's 36, bench/quality -2.0% (the pyramid's V grooves -15%), the real
// suite -0.4%; no case higher by more than 0.3%; residual texture and Dmax
// unchanged (normals only). α = 0.4: -1.6 / -1.5 / -1.2%; 0.6: -2.6 /
// -1.8 / -1.1% with the broad torus's V grooves +1.4%. The reach alone
// (the ball's move): -0.3 / -1.0 / -0.5%, bench/quality -1.7%, sydney's
// bumps +1.4%; the facet's move alone (the cone): -1.9 / -0.6 / -0.6%, the
// V-groove walls above +1.3% to +3.4%.
//
// Texture-labelled facets (session 25): Eq. 2 labels texture not only
// relief but surface points whose R_i spans several facets with no plane
// or quadric holding a share δ, as where the small facets of a low-poly
// model meet; on the spot check's faerie (bumps) 11% of the points are
// such, with exact input normals, and their output normals were 11° off
// on average. Texture points now pass through the
// exactness tests too (not the move's ramp: nothing moved where texture
// stayed in place), with the 4° test also asking that their k nearest
// neighbors' input normals agree within φ, as the still test does: a
// relief's input normals turn from point to point (bumps, domes), and a
// flat one's (scale plates, groove walls) is tilted farther than 4° and
// moved, or its fitted normals do not reach towards it. Against the two
// changes above, quick runs of the same 114 cases: -2.8% normal error on
// the spot check's 30 dense reliefs (domes -6% to -10%, sydney's bumps
// -6%), -1.0% on its waves and grooves, -1.7% on the broad 36 (animx's
// domes -15%), the real suite -0.2% (the saddle -1.1%, the disc -0.9%),
// bench/quality +0.02% (the pyramid +0.2%); no case higher by more. Without
// the agreement in the 4° test, -3.0 / -1.0 / -1.9% and the real suite
// -0.7% (the blob -4%), but the plane with domes 0.0026° -> 0.0036°
// (+37%): dome flanks near their feet, exact and within 4°, took their
// tilt.
//
// Small facets (session 28): the facet F_i needs m = facet_members (4)
// members among the K, not k (8). A low-poly model subdivided once has
// facets a few point spacings across, which hold fewer than 8 of a point's
// 24 nearest: on the spot check's faerie (bumps), 23k of the 74k points
// whose input normals are exact were not taken, 11.6° off on average, most
// for want of members. Four members in the tangent plane, spread in two
// directions, with the other neighbors off by an edge's jump, are still a
// facet's: a bump's or a wave's flank turns from point to point, so its
// neighbors lie just past φ (transitional) and few agree within it. Run
// with --keep-input-facet-members 8 against the default on the spot
// check's 96 cases and both quality suites (bench/quality_real_notes.md,
// session 28), normal error: -2.86% on the 30 dense reliefs (the mocap
// figure's bumps -15.9%, the dwarf's -10.2%), -0.52% on the 30 waves and
// grooves, -2.02% on the broad check's 36 (the grail's bumps -14.2%), no
// case higher by more than 0.05% (waves); bench/quality -0.02%, the real
// suite -0.36% (the spider -1.4%, the human -1.3%; the knot +0.015%, the
// most); residual texture
// and Dmax unchanged (normals only). m = 3: -3.08 / -0.56 / -2.20%, with
// the waves higher by up to 0.07% (the dinosaur's) instead of 0.05%.
//
// A larger move where the relief is not engraved (session 32): μ = 3
// instead of 1, except where the counter-move limit read the relief as
// sparse engraving (μ = still_move_engraved = 1 there). On low-poly
// models the update rounds the creases between small facets near relief,
// moving their points by 1-1.5 λ, so the move test turned their exact
// input normals away: on the spot check's faerie (bumps) 13k points with
// exact input normals (under 1°) kept output normals 11° off, and the
// cloud's normal error ended above the input's (6.06° against 5.12°). But
// the walls of sparse V grooves are as flat and exact as facets, are
// labelled surface by Eq. 2 where they are wide, and move as little:
// there μ = 3 took their tilt (bench/quality's pyramid +7.9%, four unseen
// models' V grooves +1% to +6%), and neither the reach nor the move told
// them apart (the pyramid's taken walls: reach ratio median 0, moves
// 1.2-1.5 λ, like the faerie's facets). Sparse engraving is what the
// counter-move limit already recognizes (V grooves lean -0.36 to -1.0).
// Measured on both quality suites and the spot check's 96 unseen cases
// (bench/quality_real_notes.md, session 32).
//
// Shallow edges (session 36): more than t transitional neighbors are
// allowed in F_i's test where their input normals lie on at most g =
// facet_groups other facets,
//
//   T_i = { j among the K : φ < ∠(ñ_j, ñ_i) <= c φ },   |T_i| <= t  or  G(T_i) <= g,
//
// G counting the groups of T_i's normals, each within φ of the first
// normal of its group (taken in the order of distance), and each group
// flat: its points within e λ on average of the plane of its first point
// and normal. A facet edge of a few degrees puts every neighbor across it
// between φ and c φ, but on one other facet, whose normals agree and whose
// points lie in its plane; a flank's normals turn from point to point and
// fall into many groups, and normals that alternate over one plane (noise,
// two directions) are not the plane's. On the spot check's faerie (bumps),
// points with exact input normals that did not move but lie within a
// spacing or two of a shallow edge kept fitted normals 3.3° off on average,
// most for want of t (a low-poly model subdivided once has many edges of
// 1-3°). Quick runs against g = 0 (the rule, normal error, geometric means;
// residual texture and Dmax unchanged but where lower_raised_cells sinks
// along the output normals, within 0.04%): the spot check's 30 dense
// reliefs -1.94% (the epileptic's bumps -7.6%, sydney's -4.5%, now under
// its input's, the faerie's -4.4%), its 30 waves and grooves -1.84% (U
// grooves -0.3% to -10.3%), the broad check's 36 -2.62% (the torus's U grooves
// -14%), the real suite -0.50% (the person -1.9%, the disc -1.8%),
// bench/quality -0.08%; the most a case rose, +0.37% (the broad torus's
// waves; sydney's waves +0.28%, the real suite's knot +0.08%, bench/
// quality's torus +0.10%): wave flanks whose transitional normals fall into
// two groups. g = 3 (measured before the groups' flatness test): the
// real suite -0.59%, bench/quality -0.15% with the torus +0.19%
// (bench/quality_real_notes.md, session 36).
//
// Normals the output reaches (session 37): after the tests above, an exact
// ñ_i (its k nearest neighbors within e λ of its tangent plane; not the
// facet test) that none of them took is taken, however far the points moved
// and whatever its neighbors' input normals, where
//
//   ∠(ñ_i, n'_i) <= θ_r,
//   min_{j ∈ R_i, |p_j - p_i| <= ρ, j ≠ i} ∠(n''_j, ñ_i) <= α_r ∠(ñ_i, n'_i),
//
// with θ_r = reached_angle_deg, α_r = reached_share and n'' the output
// normals after the tests above (the input normals they took included), so
// a facet that the tests took in part reaches the rest of it. Texture
// points too (unless texture_facets is off), but nowhere where the relief
// reads as sparse engraving (`engraved`; reached_engraved lifts that).
//
// Why: where the update rounded a shape tighter than σs (a thin limb, a
// rim, a finger) the fit turns each small facet's normal by 5-30°, and the
// move test turns the input normal away, but somewhere within ρ the output
// passes through the facet's own normal again, or the tests above took it
// there: the output normals reach ñ_i. Relief the update removed leaves no
// output normal near its own: a wave's flank or a scale's top is as exact
// as a facet and tilted as much, but the output normals around it are the
// base's. On the spot check's outputs, of the exact input normals 4-30°
// from the output's, the nearest output normal within ρ was at least half
// the tilt away on 85-94% of those on V grooves, waves and scales, and
// under a quarter of it on 72-76% of those on the faerie's and sydney's
// bumps. Sparse V grooves are the exception: the tests above take their
// flat walls in places (8.5k wall points 10.9° off on the broad rod's), and
// the walls reached from there (the rod +13.9%, the torus +7.9%), hence
// the engraved side is left out, as still_move_engraved does for them.
// Quick runs against θ_r = 0 (the rule, normal error, geometric means;
// residual texture and Dmax unchanged): the spot check's 30 dense reliefs
// -1.76% (sydney's and the faerie's bumps -5.2%, the faerie's now under
// its input's), its 30 waves and grooves -0.86% (U grooves to -6.7%;
// cases worse than their input 4 -> 2), the broad check's 36 -0.73%; the
// most a case rose: the AT-AT's V grooves +3.0% (relief leaning -0.36, not
// engraved), U grooves on the axe and the rod +1.7% and +2.0%, waves up
// to +1.1%. Taking texture points only where their neighbors' input
// normals agree (as above) kept about a quarter less of the gain and none
// of the loss; surface points only, half the gain (bench/
// quality_real_notes.md, session 37).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// The most other facets KeepInputNormalsParams::facet_groups may allow.
constexpr int kMaxFacetGroups = 8;

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
  /// θ_s: an exact input normal is also taken up to this angle of the output
  /// normal where the surface stayed (see above), in degrees; in [0, 90), 0
  /// takes none by this test (before session 23).
  double still_angle_deg = 20.0;
  /// μ: ... where nothing within ρ moved by more than this, in units of λ;
  /// >= 0. 3 since session 32, 1 before (below); still_move_engraved
  /// where the relief reads as sparse engraving.
  double still_move = 3.0;
  /// μ where `engraved` is set (below), in units of λ; >= 0.
  double still_move_engraved = 1.0;
  /// The relief reads as sparse engraving: limit_counter_moves.h's side -1
  /// (lean <= -engraved_min_lean, texture at most engraved_share of the
  /// cloud). remove_texture fills it from the update's last pass.
  bool engraved = false;
  /// φ: ... and the input normals of its exact_neighbors nearest neighbors
  /// lie within this angle of it, in degrees; in [0, 90).
  double still_uniform_deg = 1.0;
  /// K: how many nearest neighbors the facet test (above) reads; >= 0, 0
  /// turns it off (before session 24); fewer than exact_neighbors reads
  /// exact_neighbors.
  int facet_neighbors = 24;
  /// m: the facet (F_i above) needs at least this many members among the K;
  /// >= 3. 8 (exact_neighbors) before session 28 (below).
  int facet_members = 4;
  /// s: the facet's members must spread in two directions: the second
  /// eigenvalue of their covariance at least this share of the first; in
  /// (0, 1].
  double facet_spread = 0.1;
  /// c: neighbors whose input normal lies between φ and this multiple of φ
  /// from ñ_i (at most 90°) turn gradually (not across an edge); >= 1.
  double facet_jump = 3.0;
  /// t: at most this many such neighbors among the K; >= 0.
  int facet_transitional = 2;
  /// g: more than t such neighbors are allowed where their input normals
  /// lie on at most this many other facets (each within φ of one normal:
  /// the far side of a shallow edge or the facets around a vertex, not a
  /// gradual turn; see "Shallow edges" above); in [0, kMaxFacetGroups], 0
  /// counts t alone (before session 36). Python keep_input_facet_groups.
  int facet_groups = 2;
  /// α: where the surface stayed, ñ_i is taken only if some output normal
  /// within ρ lies within α ∠(ñ_i, n'_i) of it (the reach, below); in
  /// [0, 1), 0 reads the cone instead (before session 25).
  double still_reach = 0.5;
  /// Where a point within ρ moved by more than μ λ, the surface also counts
  /// as stayed if none of ñ_i's facet within ρ did (below); false: the move
  /// is read over all of them only (before session 25).
  bool still_facet_move = true;
  /// Texture points (Eq. 2) may take an exact input normal too, where the
  /// nearest neighbors' input normals agree (below); false: they keep n'_i
  /// (before session 25).
  bool texture_facets = true;
  /// θ_r: an exact input normal no test above took is taken up to this
  /// angle of the output normal where the output normals within ρ reach it
  /// (see "Normals the output reaches" above), in degrees; in [0, 90), 0
  /// takes none this way (before session 37).
  double reached_angle_deg = 30.0;
  /// α_r: ... some output normal within ρ must lie within α_r ∠(ñ_i, n'_i)
  /// of ñ_i; in (0, 1).
  double reached_share = 0.15;
  /// Take them where the relief reads as sparse engraving (`engraved`) too;
  /// false: not there (see above).
  bool reached_engraved = false;
};

struct KeepInputNormalsResult {
  Normals normals;        ///< #P by 3 unit normals
  std::size_t kept = 0;   ///< points whose output took the input normal, fully or in part
  std::size_t exact = 0;  ///< ... of which taken fully as exact (θ, e above) and not for the move
  std::size_t still = 0;  ///< ... of which (of exact) taken where the surface stayed (θ_s above)
  std::size_t facets =
      0;  ///< ... of which (of exact) taken only because the facet test found their facet
  std::size_t texture = 0;  ///< ... of which (of exact) labelled texture by Eq. 2
  /// ... of which (of kept, not of exact) taken because the output normals
  /// reach them (θ_r, α_r above)
  std::size_t reached = 0;
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
