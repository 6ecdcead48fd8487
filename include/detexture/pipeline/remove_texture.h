// The whole method of Sun et al. 2019 (Secs. 4-6) as one call: neighborhoods,
// normals when the input has none, texture identification (Eq. 2), Gaussian
// texture removal (Eq. 1), rolling-guided structure recovery (Eqs. 3-8) and
// the position update (Eqs. 9-10, or our global solve).
//
// This is what the command line and the bindings call. Every stage is also a
// free function of its own (see the headers next to this one) for callers who
// want to reuse neighborhoods or run a stage alone.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "detexture/geometry/drop_opposite_neighbors.h"
#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/geometry/face_normals.h"
#include "detexture/geometry/limit_neighborhoods_to_mesh.h"
#include "detexture/geometry/orient_normals.h"
#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/geometry/shrink_to_thin_parts.h"
#include "detexture/pipeline/detect_texture.h"
#include "detexture/pipeline/drop_neighbors_across_surfaces.h"
#include "detexture/pipeline/estimate_texture_scale.h"
#include "detexture/pipeline/filter_normals_gaussian.h"
#include "detexture/pipeline/filter_normals_rolling.h"
#include "detexture/pipeline/fit_normals_to_positions.h"
#include "detexture/pipeline/keep_input_normals.h"
#include "detexture/pipeline/limit_counter_moves.h"
#include "detexture/pipeline/limit_sink_moves.h"
#include "detexture/pipeline/limit_tip_moves.h"
#include "detexture/pipeline/lower_raised_cells.h"
#include "detexture/pipeline/repair_folds.h"
#include "detexture/pipeline/update_positions.h"
#include "detexture/threads.h"
#include "detexture/types.h"

namespace detexture {

/// A length given in the cloud's units ("0.5"), as a fraction of the
/// bounding-box diagonal d ("0.02d"), as a multiple of the neighborhood
/// radius r ("0.5r"; not for r itself), or, for r alone, as a multiple of
/// the texture radius estimated by estimate_texture_scale ("1.5t"; "auto" is
/// 1.5t).
struct Length {
  enum class Unit { Absolute, Diagonal, Radius, Texture };
  double value = 0.0;
  Unit unit = Unit::Absolute;
  /// The length in the cloud's units, given d and the resolved r (Texture
  /// lengths are resolved by remove_texture, not here).
  double resolve(double diagonal, double radius) const {
    return unit == Unit::Diagonal ? value * diagonal
           : unit == Unit::Radius ? value * radius
                                  : value;
  }
};

/// Parse "0.5", "0.02d", "0.5r", "1.5t" or "auto" (= 1.5t); throws std::invalid_argument with a
/// sentence for anything else or a non-positive value.
Length parse_length(const std::string& text);
std::string to_string(const Length& length);

/// Every parameter of the method. r is resolved against the input's
/// bounding-box diagonal d, the other lengths by default against r, so that
/// setting r alone rescales the whole method. The stage structs' own length
/// fields are ignored and filled from these.
struct RemoveTextureParams {
  /// r: radius (not diameter) of the neighborhoods R_i. By default 1.5 × the
  /// texture radius R that estimate_texture_scale finds (the rule the
  /// benchmarks use: r = 1.5 R), kept below the thickness of the shape's
  /// thin parts when it has them (choose_radius); when it finds no texture,
  /// `fallback_radius`. An explicit length ("0.05", "0.02d") skips the estimate.
  Length radius{1.5, Length::Unit::Texture};
  /// r when the radius is a multiple of the texture radius but no texture is
  /// found: 0.02 d, raised to give at least `fallback_neighbors` neighbors.
  Length fallback_radius{0.02, Length::Unit::Diagonal};
  double fallback_neighbors = 30.0;  ///< see fallback_radius; >= 3
  /// Texture-scale estimate used when r is in units of the texture radius.
  EstimateTextureScaleParams scale;
  /// Refuse (throw std::invalid_argument before building the neighborhoods)
  /// when the mean neighborhood would hold more than this share of the
  /// cloud, or more than max_mean_neighbors points: memory and time grow as
  /// r² (with max_neighbors set, the capped count is what is checked). Set
  /// allow_large_radius to run anyway.
  double max_neighbor_share = 0.2;
  double max_mean_neighbors = 3000.0;
  bool allow_large_radius = false;
  /// Warn when r holds fewer neighbors than this on average (and say which r
  /// would hold 30).
  double min_mean_neighbors = 10.0;
  /// λ: RANSAC distance threshold (Eq. 2). Bumps lower than λ count as surface.
  Length lambda{0.05, Length::Unit::Radius};
  /// Quadric underlying surface (Eq. 2, see detect_texture.h): the tightest
  /// radius of curvature the underlying surface may have; tighter is texture.
  Length min_surface_radius{0.5, Length::Unit::Radius};
  /// σs: spatial scale of the normal filters (Eqs. 1, 3). Texture smaller than
  /// σs is smoothed away.
  Length sigma_s{1.0, Length::Unit::Radius};
  /// σp: spatial scale of the position-update weights (Eqs. 9-10).
  Length sigma_p{0.5, Length::Unit::Radius};
  /// Global position update: neighbors closer than this enter the solve.
  Length solve_radius{0.5, Length::Unit::Radius};
  /// No point moves farther than this multiple of the texture height found
  /// (the 99th percentile of the texture points' heights above the surface
  /// fitted to their own neighborhood, Eq. 2's models), plus λ; 0 = no limit (the
  /// paper). Without it, weakly anchored texture on tightly curved parts
  /// (limb tips) could be carried 3-4 times the texture's height off the
  /// surface by the global update. 1.25 was measured against 1.5, both at
  /// σr 45° (quick runs of both suites' cases, bench/quality_real_notes.md):
  /// the person's Dmax 1.42 → 1.22 × the input's, the spider's 1.70 → 1.55,
  /// nothing else changed; at 1 a lone bump taller than the 99th percentile
  /// keeps part of its height (0.0045 of a bump 0.03 high, against 0.0013).
  double move_limit = 1.25;
  /// Moves against the relief (limit_counter_moves.h; the global update and
  /// the local ones alike): where the texture points that moved by more than
  /// half the texture height went mostly inward (raised relief), no point
  /// moves outward by more than limit × the texture height (report
  /// texture_height, which fills height). This is what carried points past
  /// the relief at concave junctions, bridged by the filtered normals.
  /// Measured (bench/quality_real_notes.md, session 19; quick runs to three
  /// decimals): on 30 unseen models with dense reliefs Dmax over 1.25 × the
  /// input's in 12 instead of 19, residual texture -3.7% and normal error
  /// -0.5% (geometric means); the spider's residual -10%, its Dmax 1.55 ->
  /// 1.34 ×; two U-groove cases +3-4% in residual (their update lowers the
  /// ridges between the grooves, which reads as raised relief); nothing else
  /// in either suite worse. limit 0 turns it off (before session 19). Since
  /// session 27 the second update over waves leaves the points it released
  /// free and asks for a clearer lean, and the limit is an eighth of the
  /// height instead of a quarter: on the 96 unseen cases -0.3% to -1.9%
  /// residual texture per group, three of those U grooves -3% (the axe's
  /// +2.3%).
  LimitCounterMovesParams counter_moves;
  /// Moves past the tips of the relief (limit_tip_moves.h; after the counter
  /// moves, with every update): a point that is the top of its relief within
  /// the solve radius (no neighbor more than slack × λ above it along its
  /// input normal, one at least depth × λ below) ends at most slack × λ above
  /// its highest neighbor; the bottom of a groove, likewise below. Measured
  /// (bench/quality_real_notes.md, session 26): the engine block's Dmax 1.41
  /// -> 1.18 × the input's; on 114 cases of both suites and the spot checks,
  /// Dmax over 1.25 × in 36 instead of 40, residual texture -0.1% to -0.2%
  /// per group, no case worse. radius and lambda are filled here; depth 0
  /// turns it off (before session 26).
  LimitTipMovesParams tips;
  /// Moves below a point's own relief (limit_sink_moves.h; after the tips,
  /// with every update): where the relief was raised (counter_moves' side)
  /// and a neighbor within the solve radius rises at least depth × λ above
  /// a point along its filtered normal, the point sinks no farther than the
  /// texture height (report texture_height, which fills height), or than
  /// its own height above the surface fitted to its neighborhood (Eq. 2's
  /// nearest model) plus slack × λ where that is more. Measured
  /// (bench/quality_real_notes.md, session 35): the spider's Dmax 1.34 ->
  /// 1.10 × the input's; see the header. height, radius and lambda are
  /// filled here; slack 0 turns it off (before session 35).
  LimitSinkMovesParams sinks;
  /// Dense raised cells lowered to their feet (lower_raised_cells.h; after
  /// the output normals): where the relief leans engraved and more than
  /// counter_moves.engraved_share of the points are texture (scales packed
  /// edge to edge, whose gaps the update lifted to the cells' tops), each
  /// point sinks to the cells' feet: the lowest input (2%) below the output
  /// around each neighbor within the solve radius, the 10% quantile of that
  /// over the point's neighbors, then its mean over them.
  /// Measured (bench/quality_real_notes.md, session 31): see the header.
  /// min_lean, min_share and radius are filled here; enabled = false is
  /// the output on the cells' tops (before session 31).
  LowerRaisedCellsParams raised_cells;
  /// Global update: surface points are anchored at their input positions
  /// less the farther they sit from the surface fitted to their own
  /// neighborhood (Eq. 2's models): by exp(-h²/(2 s²)) with s this multiple
  /// of λ (update_positions.h). Noise and the flanks of waves then leave
  /// with the texture. 0 anchors every surface point fully (before session 6).
  double anchor_height = 0.5;
  /// Global update: surface points are also anchored less the more their
  /// input normal turns from the filtered normal: by exp(-θ²/(2 a²)) with a
  /// this angle in degrees (update_positions.h); ≥ 0, 0 = off (before
  /// session 12). A point within λ of its fitted model but tilted against the
  /// underlying surface sits on the foot or flank of a feature, or in noise.
  /// 15° was measured against 10° and 20° on both quality suites and on 30
  /// textured models no suite uses (bench/quality_real_notes.md, session
  /// 12): residual texture -14% to -22% on the cube with bumps, the noisy
  /// cube, the multiscale sphere, the noisy ellipsoid and the saddle; at most
  /// +3% anywhere (dense scales on a cylinder); at 10° the gains were larger
  /// but the scales lost 9%.
  double anchor_angle = 15.0;
  /// Keep at most this many nearest neighbors in R_i (0 = all).
  int max_neighbors = 0;
  /// Neighbors used to estimate and orient normals when the input has none.
  int normal_neighbors = 16;
  /// Re-orient the input normals consistently (Hoppe MST) before filtering.
  bool reorient = false;
  /// How estimated (or reoriented) normals are oriented: the side each
  /// connected part faces, and the cross-sheet angle (orient_normals.h).
  /// Not used when the input's normals are kept, nor for meshes whose
  /// normals come from their faces.
  OrientNormalsParams orient;
  /// Estimate the normals from the positions (as for a cloud without
  /// normals) even when the input has them: for scans whose normals are
  /// noisy, smoothed by the scanner or wrong in places. With faces and
  /// use_faces, the faces give them. report.normals_ignored says it happened.
  bool ignore_input_normals = false;
  /// Memory guard, bytes: before the neighborhoods are built their size is
  /// estimated from a sample (estimate_neighborhoods_memory.h), and a run
  /// that would need more is refused with a ResourceLimitError saying what
  /// to change. 0 = 80% of the physical memory (default_memory_limit());
  /// the largest uint64 = no limit.
  std::uint64_t memory_limit = 0;

  /// Neighbors facing away from p_i by more than this angle are on another
  /// sheet of a thin part and leave R_i (drop_opposite_neighbors.h).
  DropOppositeNeighborsParams sheets;
  /// Clouds, after texture detection: pairs of neighbors neither of which
  /// lies on the other's underlying surface leave R_i
  /// (drop_neighbors_across_surfaces.h; 180° keeps them, the paper). Meshes
  /// keep theirs: the mesh-path limit below keeps R_i on its sheet.
  DropNeighborsAcrossSurfacesParams surface_split;
  /// On parts thinner than r (limbs, fingers), R_i shrinks to the distance of
  /// the part's back, but not below min_radius_fraction × r
  /// (shrink_to_thin_parts.h; 1 = the paper). Its radius is filled from r.
  ShrinkToThinPartsParams thin_parts;
  /// Meshes (the overload with faces, use_faces true): R_i keeps only the
  /// neighbors an edge path reaches within path_factor × r
  /// (limit_neighborhoods_to_mesh.h; 0 keeps R_i Euclidean). Its radius is
  /// filled from r.
  LimitNeighborhoodsToMeshParams mesh_paths;
  DetectTextureParams texture;           ///< δ, confidence, RANSAC cap, seed (λ from above)
  FilterNormalsGaussianParams gaussian;  ///< sub-neighborhood switch (σs from above)
  FilterNormalsRollingParams rolling;    ///< σr, iterations, guidance (σs from above)
  UpdatePositionsParams update;  ///< mode, isotropy angle, anchors (σp, solve radius from above)
  /// Output normals fitted to the updated positions and blended with the
  /// filtered ones where the two disagree (fit_normals_to_positions.h; the
  /// default); false outputs the filtered normals, as the paper does.
  /// Clouds, and meshes with use_faces false; meshes with faces take theirs
  /// from the output's faces.
  bool fit_normals = true;
  /// The fit's range scale and largest turn; its σ is fit_sigma and its
  /// radius the solve radius.
  FitNormalsToPositionsParams output_normals;
  /// σ of the output-normal fit (fit_normals_to_positions.h).
  Length fit_sigma{0.3, Length::Unit::Radius};
  /// The output-normal fit's range weights read the input normals, where the
  /// input had them, instead of the filtered ones (fit_normals_to_positions.h,
  /// range normals): the filtered normals round the facets, seams and rims
  /// of the shape at σs, so the fit leaned across them. Estimated normals
  /// (an input without normals) are PCA fits that round the same way and
  /// carry the noise: measured no better there, the filtered ones weigh the
  /// fit. Measured (bench/quality_real_notes.md, session 18), normal error:
  /// the spider -3.1%, the duck -2.0%, the person -1.5% (4.94° -> 4.87°);
  /// the blob +1.4%, the noisy ellipsoid +0.9%, the multiscale sphere
  /// +0.9%, the noisy cube +0.7%; 30 unseen dense reliefs -1.6%. false
  /// weighs by the filtered normals (before session 18).
  bool fit_range_input_normals = true;
  /// Input normals kept where the output surface is the input surface
  /// (keep_input_normals.h; with fit_normals): where no point within the
  /// solve radius moved by more than low λ the input normal is taken, from
  /// high λ the fitted one; its radius and λ are filled from above.
  /// Measured (bench/quality_real_notes.md, session 18), normal error: the
  /// cube with bumps -9.7%, the blob -6.6%, the saddle -3.6%, the person
  /// -3.1%; the torus +0.3% the most; with the normals estimated, -6.3% to
  /// +0.3%; the noisy cases unchanged (their points move). high 0 turns it
  /// off (before session 18). Exact input normals (noise-free: their
  /// nearest neighbors lie in their tangent plane) are also taken where
  /// they lie within exact_angle_deg (4°) of the fitted one, however far
  /// the points moved (session 21): normal error -7.7% on the suites, -5.6%
  /// and -3.3% on 60 unseen cases, the noisy cases unchanged;
  /// exact_angle_deg 0 turns that off (before session 21). Where nothing
  /// within the solve radius moved by more than λ, exact input normals are
  /// taken up to still_angle_deg (20°) from the fitted one when their
  /// neighbors' input normals agree and the fitted normals around turn as
  /// much (facets; session 23): -1% normal error on 60 unseen cases, the
  /// suites within ±0.2%; still_angle_deg 0 turns that off. Both tests also
  /// find a facet past its edges among facet_neighbors (24) nearest
  /// (session 24): -1.8% to -3.7% normal error on 96 unseen cases, -2.9%
  /// and -1.5% on the suites; facet_neighbors 0 turns that off. Where the
  /// surface stayed, the fitted normals around must reach towards the input
  /// normal (still_reach, 0.5), not merely turn as much, and the surface
  /// also counts as stayed where the point's facet did not move though
  /// relief beside it did (still_facet_move; session 25): -1.2% to -2.2%
  /// normal error on 96 unseen cases, -2.0% and -0.4% on the suites;
  /// still_reach 0 and still_facet_move false turn that off. Texture points
  /// whose neighbors' input normals agree pass the exactness tests too
  /// (texture_facets; session 25): a further -1.0% to -2.8% on 96 unseen
  /// cases, the suites within +0.02%. A facet needs facet_members (4)
  /// members among the 24, not 8 (session 28): small facets of low-poly
  /// models, -0.5% to -2.9% normal error on 96 unseen cases, the suites
  /// -0.02% and -0.36%; facet_members 8 is the behaviour before.
  KeepInputNormalsParams keep_input;
  /// Exact input normals in the update (session 43; clouds, with
  /// fit_normals): before Sec. 6's update, a point's input normal replaces
  /// its filtered normal where keep_input's exactness, still and facet tests
  /// would take it were nothing to move (not its move ramp, nor its reach),
  /// for the update and every stage after it. Why: the filters round the
  /// facets and rims of a shape at σs, and the update followed, carrying
  /// facets that the texture never touched off the surface (a low-poly
  /// base's flat facets; sydney's bumps on the spot check: 81% of the points
  /// plain facets, whose share of the squared error grew 40 × in the
  /// coarse check). The input normal there is the surface's, when it is
  /// exact. Where the relief then reads as sparse engraving
  /// (limit_counter_moves.h's side −1: V grooves; read per tile in tiled
  /// runs, like the side itself), the update runs again
  /// with the filtered normals: a V groove's walls are as flat and exact as
  /// facets, and holding them kept the grooves (the broad rod's +41% normal
  /// error). Noisy input normals fail the exactness test and change nothing.
  /// With fit_normals false (the filtered output normals, the paper's) the
  /// output keeps no input normal, and neither does the update. Measured
  /// (bench/quality_real_notes.md, session 43): on the spot check's 156
  /// unseen cases residual texture -0.3% to -6.8% and normal error -0.6% to
  /// -3.3% per group (geometric means), cases worse than the input 4 -> 2
  /// in residual texture, 10 -> 9 in normal error; the real suite's blob
  /// and saddle -20% in residual texture, the knot +0.6%, the noisy cases
  /// unchanged. false fits the filtered normals everywhere (before session
  /// 43).
  bool update_input_normals = true;
  /// Waves left, second pass (clouds, with fit_normals and the blend).
  /// The output-normal fit flags the surface points where waves or grooves
  /// stayed in the positions (fit_normals_to_positions.h, waves): their
  /// crests and troughs were labelled underlying surface by Eq. 2's planes
  /// and held by their anchors. When the flagged points are more than
  /// wave_share_low of the surface points, the global update runs again with
  /// the anchors of the flagged points scaled by (anchor_texture /
  /// anchor_surface)^t, t ramping from 0 at wave_share_low to 1 at
  /// wave_share_high, so that they follow the filtered normals like texture.
  /// The output normals stay those of the first pass. The share is a gate on
  /// the whole cloud (each tile's, in tiled runs): one flagged point alone
  /// cannot tell a wave's crest from a rounded edge the filtered normals
  /// smooth, where the same statistics hold, but waves cover the surface and
  /// edges are lines. Measured (bench/quality_real_notes.md, session 14): the
  /// suites' waves and grooves flag 11.5-46% of their surface points; the 14
  /// other suite cases and 30 unseen ones at most 8.6%, the engine block's
  /// mesh filtered as a cloud 10.5%. Residual texture: -30% on the torus
  /// with waves, -19% on the noisy U grooves, -8% on the knot, -4% on the V
  /// grooves; nothing else changed. A ramp from 0.08 to 0.16 gave the V
  /// grooves -8% but reached a case without waves (+1.8%). Shares in [0, 1],
  /// low < high; low >= 1 turns the second pass off.
  double wave_share_low = 0.1;
  double wave_share_high = 0.2;
  /// Waves left, second pass: the anchors of the other surface points (the
  /// ones the fit did not flag) are scaled by wave_rest_anchor^t, with the
  /// same ramp t. Why: the flags sit at the crests and troughs where the
  /// fit departs most; the flanks and the crests beside them are held at
  /// their input heights by their own anchors, so about half of the waves'
  /// height stayed (the knot: output heights 0.44 × the input's). Held less
  /// firmly, they follow the filtered normals too. Measured (bench/
  /// quality_real_notes.md, session 38; 0.3 against 1): residual texture
  /// -6.3% on the 42 unseen waves and grooves that run the second pass
  /// (geometric mean; normal error -0.3%, Dmax over 1.25 × the input's in
  /// the same 17); the suites' torus with waves -8.7%, noisy U grooves
  /// -7.7%, knot -6.7%, V grooves -2.4%, and no other case moves. Lower
  /// factors remove more and cost more Dmax on thin parts:
  /// 0.1 gave -10.4% on the unseen 42 but one more case over 1.25 × Dmax
  /// and the epileptic's waves 1.77 -> 1.98 ×; 0.01, -11.2% and four more.
  /// In (0, 1]; 1 holds them fully (before session 38).
  double wave_rest_anchor = 0.3;
  /// Waves left, second pass: a point in the upper half of its input relief
  /// within the solve radius moves outward by at most wave_ceiling λ, and
  /// one in the lower half inward by at most as much (limit_tip_moves.h,
  /// the ceiling). Why: with the anchors lowered, crests on the rims of thin
  /// parts and at concave junctions follow the filtered normals outward
  /// across the bend; the spot check's largest distances from the
  /// underlying surface came from them (bench/quality_real_notes.md,
  /// sessions 38 and 39). Measured against 0 on the 42 unseen waves and
  /// grooves that run the pass: Dmax over 1.25 × the input's 17 -> 14,
  /// residual texture -0.1%; 0.5 gave 14 and +0.02%, 2 gave 15. Its cost:
  /// floors of grooves wider than the solve radius on a bent base read as
  /// the upper half (bench/quality's noisy U grooves +0.69% residual).
  /// >= 0; 0 turns it off (before session 39).
  double wave_ceiling = 1.0;
  /// Output normals where no waves are left (clouds, with fit_normals and
  /// the blend). The blend keeps the filtered normals where the fit departs
  /// from them by a mean angle ā over 2°, against waves or grooves left in
  /// the positions; where none are left, the fit is the better normal there
  /// too, since the filtered normals round the shape's own curvature at σs.
  /// So the output mixes the blend with the open window
  /// (fit_normals_to_positions.h, open: the fit up to ā = 5°, the filtered
  /// normal from 10°) and the blend's own window by t, normalized, t ramping
  /// from 0 at blend_share_low to 1 at blend_share_high of the surface
  /// points flagged as waves (the share wave_share_low reads). Measured
  /// (bench/quality_real_notes.md, session 15), normal error: -1% to -19%
  /// on 10 suite cases (the disc -19%, the duck -10%, the person 5.38° ->
  /// 5.03°, the bull 5.75° -> 5.45°), +2.7% on the scaled cylinder, +1.4%
  /// on the noisy engine block; -4.8% on 30 unseen cases of dense relief and
  /// +0.5% on 30 unseen waves and grooves, where grooves that flag under 10%
  /// pay up to +4.1%. Without the gate the waves and grooves pay +21%, the
  /// torus with waves +110%. Shares in [0, 1], low < high;
  /// blend_share_high 0 keeps the blend's own window on every cloud (before
  /// session 15).
  double blend_share_low = 0.05;
  double blend_share_high = 0.1;

  /// Worker threads, >= 0; 0 = all cores (OpenMP's default, or OMP_NUM_THREADS).
  /// Applied for the duration of the call only (ScopedThreads in threads.h);
  /// the result is bitwise the same for any value.
  int threads = 0;
  /// Meshes (the remove_texture overload with faces): true takes the input
  /// normals from the faces (face_normals.h; no PCA) when the input has none,
  /// and repairs the folds the update makes (repair_folds.h); false treats
  /// the vertices as an unconnected cloud, as the paper does.
  bool use_faces = true;
  FaceNormalsParams face_normals;  ///< angle or area weights
  RepairFoldsParams folds;         ///< fold angle (enabled is ignored: use_faces decides)
};

/// Check every parameter; throws std::invalid_argument naming the bad one.
void validate(const RemoveTextureParams& params);

/// How r follows from the parameters, the diagonal d and (when r is a
/// multiple of the texture radius) the scale estimate: choice is "given",
/// "texture" (the multiple of the texture radius, kept below the estimate's
/// thin_radius when the cloud has thin parts, but not below the radius
/// holding fallback_neighbors) or "fallback" (no texture found: the larger of
/// fallback_radius and the radius holding fallback_neighbors on a surface of
/// the estimated spacing s, s √(n/π)); reason says it in words.
struct RadiusChoice {
  double radius = 0.0;
  std::string choice, reason;
};
RadiusChoice choose_radius(const RemoveTextureParams& params, double diagonal,
                           const TextureScaleEstimate& scale);

/// Callbacks for long work; any may be empty. Called from the calling thread
/// or, for progress, from one worker at a time.
struct PipelineObserver {
  std::function<void(const std::string& stage)> begin;
  std::function<void(const std::string& stage, double fraction)> progress;
  std::function<void(const std::string& stage, double seconds)> end;
  std::function<void(const std::string& message)> warning;
};

struct StageTiming {
  std::string stage;
  double seconds = 0.0;
};

struct RemoveTextureReport {
  double diagonal = 0.0;
  /// How r was chosen: "given" (an explicit length), "texture" (a multiple
  /// of the estimated texture radius) or "fallback" (no texture found).
  std::string radius_choice;
  std::string radius_reason;     ///< a sentence saying why r is what it is
  bool scale_estimated = false;  ///< `scale` holds an estimate
  TextureScaleEstimate scale;
  double radius = 0.0, lambda = 0.0, sigma_s = 0.0, sigma_p = 0.0;  ///< resolved lengths
  NeighborhoodStats neighbors;  ///< of R_i; sparse = fewer than 3 neighbors
  bool normals_estimated = false;
  bool normals_ignored = false;  ///< the input had normals; ignore_input_normals dropped them
  std::size_t normals_reestimated = 0;      ///< zero-length input normals re-estimated
  std::size_t normals_degenerate = 0;       ///< normals that could not be estimated (left zero)
  std::size_t normals_flipped = 0;          ///< by orientation
  double orientation_inconsistency = 0.0;   ///< of the normals fed to the filters
  std::size_t opposite_neighbors = 0;       ///< (i, j) pairs dropped as another sheet
  std::size_t surface_split_neighbors = 0;  ///< (i, j) entries dropped as another surface
  std::size_t thin_part_points = 0;         ///< points whose R_i shrank to a thin part
  std::size_t thin_part_neighbors = 0;      ///< (i, j) entries that left R_i with it
  std::size_t mesh_path_points = 0;         ///< points whose R_i lost vertices far along the mesh
  std::size_t mesh_path_neighbors = 0;      ///< (i, j) entries that left R_i with them
  std::size_t texture_points = 0;
  std::size_t no_plane = 0;
  double ransac_mean_iterations = 0.0;
  std::size_t empty_subneighborhoods = 0;
  int rolling_iterations = 0;
  std::size_t update_isolated = 0;
  int update_iterations = 0;
  double mean_displacement = 0.0;
  double texture_height =
      0.0;  ///< 99th percentile of the texture points' heights above their fitted surfaces
  double max_move = 0.0;          ///< the resulting move limit (0 = none)
  std::size_t moves_limited = 0;  ///< points whose move was cut to it
  /// Moves against the relief (limit_counter_moves.h), after the last
  /// update: the lean of the texture points' moves (+1 all inward: raised
  /// relief; tiled runs: the mean over the tiles, weighted by their core
  /// points), and the points whose move was cut (LimitCounterMovesResult::
  /// limited; tiled runs sum it).
  double relief_lean = 0.0;
  std::size_t counter_moves_limited = 0;
  /// Tips of the relief whose move was cut (limit_tip_moves.h), after the
  /// last update; tiled runs sum it.
  std::size_t tip_moves_limited = 0;
  /// Points held at their own relief's depth (limit_sink_moves.h), after
  /// the last update; tiled runs sum it.
  std::size_t sink_moves_limited = 0;
  /// Points lowered to the feet of dense raised cells (lower_raised_cells.h;
  /// 0 where the relief was not read as such); tiled runs sum it.
  std::size_t raised_cells_lowered = 0;
  /// Of those, or of the points it left in place, the ones the depth limit
  /// held above the cells' feet (LowerRaisedCellsParams::max_depth); tiled
  /// runs sum it.
  std::size_t raised_cells_limited = 0;
  /// Of those lowered, the points that sank along their neighbors' mean
  /// normal, their own having turned over (LowerRaisedCellsParams::
  /// max_turn_deg); tiled runs sum it.
  std::size_t raised_cells_turned = 0;
  /// Output normals not fitted to the positions (fit_normals_to_positions.h):
  /// these keep the filtered normal.
  std::size_t normals_not_fitted = 0;
  /// Output normals mixed with the filtered normal, or replaced by it, where
  /// the fit disagrees with it around the point (the blend of
  /// fit_normals_to_positions.h: waves or noise left in the positions).
  /// Tiled runs sum this and normals_not_fitted over the tiles' runs, halo
  /// points included.
  std::size_t normals_blended = 0;
  /// Output normals that took the input normal, fully or in part, where
  /// nothing near the point moved (keep_input_normals.h); tiled runs sum it.
  std::size_t input_normals_kept = 0;
  /// Points whose input normal the update fitted instead of the filtered
  /// one (update_input_normals); 0 where the relief read as sparse
  /// engraving and the update ran again without them. Tiled runs sum it.
  std::size_t input_normals_updated = 0;
  /// Surface points flagged as lying where waves or grooves stayed in the
  /// positions (fit_normals_to_positions.h, waves), and those whose anchors
  /// the second pass lowered (wave_share_low; 0 when it did not run).
  std::size_t waves_flagged = 0;
  std::size_t waves_released = 0;
  /// Points at exactly the position of an earlier point: the method ran on
  /// the distinct positions and each copy got the result of the first.
  std::size_t duplicates_merged = 0;
  double estimated_bytes = 0.0;  ///< the memory guard's estimate of the peak (0 if not run)
  /// Meshes only (the overload with faces; `mesh` says whether it ran):
  bool mesh = false;
  bool normals_from_faces = false;       ///< the input normals came from the faces
  std::size_t triangles = 0;             ///< after splitting polygons
  std::size_t triangles_reoriented = 0;  ///< turned by orient_triangles, for the normals only
  RepairFoldsReport folds;  ///< folds and flips of the input, the update and the output
  std::vector<StageTiming> timings;
};

struct RemoveTextureResult {
  Positions positions;  ///< #P by 3, texture removed
  Normals normals;      ///< #P by 3 unit normals of the output (fitted, filtered or from faces)
  std::vector<std::uint8_t> is_texture;  ///< #P, Eq. 2
  Eigen::VectorXd texture_height;        ///< #P, (p_in - p_out)·n_out: the signed texture removed
  Normals input_normals;                 ///< #P by 3, the normals the filters started from
  Positions input_positions;             ///< #P by 3, P as given (handed back, see below)
  RemoveTextureReport report;
};

/// Run the method on positions P (#P by 3) with optional input normals (#P by
/// 3, or 0 rows to estimate them). Both are taken by value: pass them with
/// std::move and they are freed as soon as they have been copied into spatial
/// order, which keeps two copies out of the peak memory; result.input_positions
/// and result.input_normals give them back. Deterministic for any thread
/// count. Exact duplicate points are merged before the neighborhoods and get
/// the result of the first copy (report.duplicates_merged), so that they cost
/// linear time. Clouds whose extent is beyond 2^±64 (±1e300, ±1e-300) run
/// scaled by a power of two, which is exact. Throws std::invalid_argument on
/// bad parameters or mismatched sizes, and ResourceLimitError when the
/// neighborhoods would exceed params.memory_limit.
RemoveTextureResult remove_texture(Positions P, Normals normals, const RemoveTextureParams& params,
                                   const PipelineObserver& observer = {});

/// The same on a mesh: P are the vertices of the polygons `faces` (as
/// read_point_cloud keeps them, face_list.h). With params.use_faces, input
/// normals, when there are none, are the angle-weighted normals of the
/// consistently oriented faces (face_normals.h), and the positions are
/// repaired so that the update folds no edge and flips no triangle
/// (repair_folds.h); the output normals are then those of the output's
/// faces. report.folds counts folds and flips (with use_faces false too,
/// where the cloud version above runs and its folds are only measured). Throws
/// std::invalid_argument as above, or when a face refers to a missing vertex.
RemoveTextureResult remove_texture(Positions P, Normals normals, const FaceList& faces,
                                   const RemoveTextureParams& params,
                                   const PipelineObserver& observer = {});

}  // namespace detexture
