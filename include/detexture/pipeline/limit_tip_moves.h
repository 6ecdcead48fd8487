// Moves past the tips of the relief (after Sec. 6, session 26): a point that
// is a tip of the input, the top of a bump or the bottom of a groove, does
// not end farther out than its own relief reached.
//
//   h_ij = (p_j - p_i)·n_i          j ∈ R_i, |p_j - p_i| <= ρ
//   hi_i = max(0, max_j h_ij),  lo_i = min(0, min_j h_ij)
//   peak: hi_i <= s λ  and  lo_i <= -d λ      t_i = (p'_i - p_i)·n_i
//   pit:  lo_i >= -s λ and  hi_i >=  d λ
//   peak: t_i > hi_i + s λ  becomes  hi_i + s λ      p''_i = p'_i + (t'_i - t_i) n_i
//   pit:  t_i < lo_i - s λ  becomes  lo_i - s λ
//
// where p are the input positions, p' the updated ones, n the input normals,
// λ the RANSAC threshold, d = depth and s = slack. A peak is a point none of
// whose neighbors within ρ rises more than s λ above it along its own normal
// while one lies at least d λ below; a pit is the same upside down. Flat
// surface (every h_ij within noise) and the flanks of relief are neither.
//
// Why: removing relief moves a bump's top inward and a groove's bottom
// outward, towards the surface under them; it never carries them farther
// out along their own normals than the relief around them reaches. Where
// the update did so, the filtered normals had rounded a place tighter than
// σs (the floor of a V groove whose walls the surface split left out of
// R_i, a wave's crest on a tight bend) and the weakly anchored texture
// followed them: the output's largest distances from the underlying surface
// come from such points (the real suite's engine block: groove floors
// carried 0.005-0.007 deeper, Dmax 1.41 × the input's; bench/
// quality_real_notes.md, session 26). The tests read only the input, so
// they hold whatever the update did, and each is one-sided: a peak may still
// sink and a pit rise by any amount. The strictness (d λ of relief on the
// other side, λ itself above the noise) leaves flat surface, plates and
// groove floors wider than ρ alone: a tip test without it held the floors
// of pits and the caps of domes (the plane with domes: residual texture ×400,
// measured offline on session 25's outputs).
//
// The ceiling (session 39; off unless `ceiling` > 0, which remove_texture
// sets for the waves' second pass alone): the relief is read again over the
// neighbors whose input normals agree with n_i (n_j·n_i >= min_cos), giving
// hi'_i and lo'_i, and
//
//   upper half: -lo'_i > hi'_i    t_i > c λ   becomes  c λ
//   lower half:  hi'_i > -lo'_i   t_i < -c λ  becomes -c λ
//
// with c = ceiling. A point nearer the top of its relief than its bottom
// is a crest or a crest's flank: removing the relief moves it inward, and
// more than c λ outward only where the filtered normals bridge a bend
// (the rim of a thin part, a concave junction) and the second pass's low
// anchors let it follow them. The lower half is the same upside down, so
// the rule holds for either sign of n. Neighbors whose normals disagree are
// the other side of a thin part, whose heights would place every point in
// the upper half. Measured (bench/quality_real_notes.md, session 39).
#pragma once

#include <cstddef>
#include <cstdint>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct LimitTipMovesParams {
  /// d: how far the relief must fall away from a tip on its other side, in
  /// units of λ; >= 0, 0 turns the limit off (before session 26).
  double depth = 2.0;
  /// s: how far a neighbor may lie beyond a tip, and the tip beyond its
  /// farthest neighbor after the update, in units of λ; >= 0.
  double slack = 1.0;
  /// ρ, the radius the tips are read within, in the cloud's units; > 0.
  /// RemoveTextureParams fills it with the solve radius (0.5 r).
  double radius = 0.0;
  /// λ in the cloud's units; > 0. RemoveTextureParams fills it.
  double lambda = 0.0;
  /// c: how far a point in the upper half of its relief may move outward
  /// (and one in the lower half inward), in units of λ; >= 0, 0 turns the
  /// ceiling off. RemoveTextureParams fills it in the waves' second pass
  /// (wave_ceiling) and leaves it 0 otherwise.
  double ceiling = 0.0;
  /// The cosine a neighbor's input normal must reach with n_i for its
  /// height to count in the ceiling's relief; in [-1, 1].
  double ceiling_min_cos = 0.5;
};

struct LimitTipMovesResult {
  Positions positions;      ///< #P by 3
  std::size_t limited = 0;  ///< points whose move was cut (tips and ceiling)
};

void validate(const LimitTipMovesParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// normals  #P by 3 unit input normals n (oriented or not: the tests are
///   symmetric under n -> -n; the ceiling's agreement test needs them
///   oriented consistently between neighbors)
/// R  the neighborhoods; only neighbors within ρ count
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
LimitTipMovesResult limit_tip_moves(const Positions& P, const Positions& updated,
                                    const Normals& normals, const Neighborhoods& R,
                                    const LimitTipMovesParams& params);

}  // namespace detexture
