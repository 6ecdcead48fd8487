// Position update (Sun et al. 2019, Sec. 6, Eqs. 9-10): move the points so
// that they fit the filtered normal field.
//
// The paper minimizes, for every point on its own with neighbor positions held
// at the input (Eq. 9 reads p'_i - p_j),
//   Σ_{j∈Ψ_i} w(p'_i, p_j, σp) ((p'_i - p_j)·n_j)²                    (Eq. 10)
// where Ψ_i, the isotropic neighborhood, keeps the neighbors whose filtered
// normal is within an angle of n_i so that points do not slide onto the
// tangent planes across a crease (Fig. 8). Eq. 9 is the same sum over R_i.
// We iterate the fixed point p'_i += Σ w ((p_j - p'_i)·n_j) n_j / Σ w to a
// tolerance.
//
// That local fit lands each point on a weighted mean of its neighbors'
// tangent planes, so a point on top of a bump wider than its neighborhood
// stays high: the texture leaves the normals but not the positions. The
// default, `Global`, instead solves one sparse least-squares problem for all
// points at once. Each point moves only along its filtered normal,
// p'_i = p_i + t_i n_i, and we minimize
//   Σ_i μ_i t_i² + Σ_i Σ_{j∈Ψ_i} w_ij ((p'_i - p'_j)·m_ij)²,   m_ij = (n_i+n_j)/|n_i+n_j|
// — every neighbor chord should lie in the tangent plane of its midpoint
// normal (exact on spheres and planes, so nothing shrinks or expands). The
// anchor weight μ_i is large for underlying-surface points (Eq. 2) and tiny
// for texture points, so texture points are carried to the surface spanned by
// their untextured surroundings, however wide the feature. Moving along the
// normal only, points never cluster at creases or open gaps. The system is
// symmetric positive definite and solved by Jacobi-preconditioned conjugate
// gradients over the members of Ψ_i within `solve_radius` (a distance cut
// keeps the graph symmetric and the solve cheap).
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

enum class UpdateMode {
  Global,     ///< ours: one least-squares solve along the normals (default)
  Isotropic,  ///< the paper's Eq. 10, point by point over Ψ_i
  Eq9,        ///< the paper's Eq. 9, point by point over R_i (Fig. 8 ablation)
};

struct UpdatePositionsParams {
  UpdateMode mode = UpdateMode::Global;
  /// σp: spatial scale of the weights w, in the cloud's units; > 0.
  double sigma_p = 0.0;
  /// Ψ_i keeps neighbors whose filtered normal is within this angle of n_i,
  /// in degrees, in (0, 180].
  double isotropy_deg = 30.0;
  /// Global: anchor weight of underlying-surface points, relative to their
  /// data weight; ≥ 0. Larger keeps them closer to where they were.
  double anchor_surface = 1.0;
  /// Global: anchor weight of texture points, relative; > 0 (keeps the
  /// problem well posed where no underlying surface is near).
  double anchor_texture = 1e-4;
  /// Global: scale s of the surface anchors' fall-off, in the cloud's units;
  /// ≥ 0. A surface point at height h above the surface fitted to its own
  /// neighborhood (detect_texture's height: noise, the flank of a wave) is
  /// anchored with anchor_texture + (anchor_surface - anchor_texture) ·
  /// exp(-h² / (2 s²)), since its input position is not the surface either.
  /// 0 anchors every surface point fully. remove_texture sets it from λ.
  double anchor_height = 0.0;
  /// Global: angle scale a of a second fall-off of the surface anchors, in
  /// degrees; ≥ 0. A surface point whose input normal (the `input_normals`
  /// argument) turns by θ from its filtered normal is anchored with a further
  /// factor exp(-θ² / (2 a²)) on the surface part of its weight: it sits on
  /// the foot or flank of a feature, or in noise, where its input position is
  /// not the underlying surface either, although it lies within λ of a fitted
  /// model. 0 turns this fall-off off. remove_texture sets it (15°).
  double anchor_angle_deg = 0.0;
  /// Global: only members of Ψ_i closer than this take part in the solve, in
  /// the cloud's units; 0 uses all of R_i.
  double solve_radius = 0.0;
  /// Iteration cap (fixed-point iterations, or conjugate-gradient steps), ≥ 1.
  int max_iterations = 200;
  /// Convergence tolerance, > 0. Local modes: a point stops when its move in
  /// an iteration is below tolerance·σp. Global: conjugate gradients stop when
  /// the residual is below tolerance times the right-hand side (2-norms).
  double tolerance = 1e-3;
  /// No point moves farther than this from its input position, in the
  /// cloud's units; 0 = no limit. remove_texture sets it from the texture
  /// height it found (see remove_texture.h), so that a point is never thrown
  /// farther off than the texture could explain.
  double max_move = 0.0;
};

struct UpdatePositionsResult {
  Positions positions;             ///< #P by 3
  int iterations = 0;              ///< Global: CG steps; local modes: the most any point took
  std::size_t isolated = 0;        ///< points whose Ψ_i held only themselves: kept in place
  double mean_displacement = 0.0;  ///< mean |p' - p|, to judge how much was removed
  std::size_t limited = 0;         ///< points whose move was cut to max_move
};

/// Fit positions to the filtered normals (#P by 3, unit, oriented). `is_texture`
/// is needed by Global and may be empty otherwise.
UpdatePositionsResult update_positions(const Positions& P, const Normals& filtered,
                                       const Neighborhoods& R,
                                       const std::vector<std::uint8_t>& is_texture,
                                       const UpdatePositionsParams& params,
                                       const ProgressFn& progress = {});

/// The same with the height of every point above the surface fitted to its
/// own neighborhood (#P, TextureDetection::height), which Global needs when
/// params.anchor_height > 0 (throws std::invalid_argument if missing).
UpdatePositionsResult update_positions(const Positions& P, const Normals& filtered,
                                       const Neighborhoods& R,
                                       const std::vector<std::uint8_t>& is_texture,
                                       const std::vector<float>& height,
                                       const UpdatePositionsParams& params,
                                       const ProgressFn& progress = {});

/// The same with the input normals (#P by 3, the normals each point came
/// with), which Global needs when params.anchor_angle_deg > 0 (throws
/// std::invalid_argument if missing).
UpdatePositionsResult update_positions(const Positions& P, const Normals& filtered,
                                       const Neighborhoods& R,
                                       const std::vector<std::uint8_t>& is_texture,
                                       const std::vector<float>& height,
                                       const Normals& input_normals,
                                       const UpdatePositionsParams& params,
                                       const ProgressFn& progress = {});

/// The same with a factor on every point's anchor weight μ_i (#P, each
/// finite and >= 0; empty = 1 everywhere; Global only). remove_texture
/// lowers the anchors of points where waves or grooves stayed in the
/// positions of a first pass (remove_texture.h, wave_share_low).
UpdatePositionsResult update_positions(
    const Positions& P, const Normals& filtered, const Neighborhoods& R,
    const std::vector<std::uint8_t>& is_texture, const std::vector<float>& height,
    const Normals& input_normals, const std::vector<float>& anchor_scale,
    const UpdatePositionsParams& params, const ProgressFn& progress = {});

void validate(const UpdatePositionsParams& params);

}  // namespace detexture
