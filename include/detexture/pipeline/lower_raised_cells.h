// Dense raised cells lowered to their feet (after Sec. 6, session 31): where
// the removed relief was cells packed edge to edge (scales), whose narrow
// gaps the update lifted to the cells' tops, the output sinks back to the
// gaps' level.
//
//   t_j = (p_j - p'_j)·n_j                 the input below the output (< 0)
//   a_i = Q_q1 { t_j : j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ }
//   b_i = Q_q2 { a_j : j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ }
//   c_i = mean { b_j : j ∈ R_i ∪ {i}, |p_j - p_i| <= ρ }
//   p''_i = p'_i + min(max(c_i, t_i - d h), 0) n_i
//
// where p are the input positions, p' the updated ones, n the output normals,
// Q_q the q-quantile (the lower one, no interpolation), q1 = low_quantile
// and q2 = spread_quantile, h the texture height and d = max_depth: no
// point ends more than d h below its own input along its normal, since
// relief h high cannot explain a deeper move (d = 0 or h = 0: no limit);
// and where a point's output normal n_i has turned more than max_turn_deg
// from m_i, the unit mean of its neighbors' output normals within ρ, n_i's
// "down" is not to be trusted: the point sinks by the same c_i along m_i
// instead, t_i and the limit read along it too (max_turn_deg = 180: no
// such test). a_i reads the lowest input around i from the
// output surface, each input point from its own output point, so a curved
// underlying surface adds no sag; b_i spreads it over ρ and lets no single
// stray point decide; c_i smooths it, so that the lowering adds no relief of
// its own (without it, the residual texture rose by up to 8% on a model
// where the lowering took 80% of Dmean off). It runs only where
//
//   lean <= -min_lean   and   texture share > min_share,
//
// with the lean of limit_counter_moves.h (the texture points' large moves
// lean outward) and the share of points Eq. 2 labels texture. These are the
// cases limit_counter_moves leaves alone because they are dense; remove_
// texture passes its engraved_min_lean and engraved_share, so the two stages
// split the engraved-leaning relief between them: sparse, it is engraved
// (limited there); dense, it is raised cells (lowered here). The positions
// only move; the normals stay as they are (the move is smooth over ρ).
//
// Why the depth limit (session 34): c_i is a mean over ρ, and where the
// update had already carried a point down from a cell's top to the feet or
// past them (a concave junction, its output normal 30-80° off the true
// one), the full c_i sank it a further 0.0065-0.007, more than the scales'
// 0.005 height: on synth's sydney with dense scales, the 25 points over
// 1.25 × the input's Dmax were all such points, 2 × max_move from their
// inputs. Such a point's own t_i is positive (its input above its output),
// so the limit t_i - d h lets it sink little or not at all, while a point
// on a top whose input was in a gap (t_i = -h) may still sink by h. The
// one point still over 1.25 × the input's Dmax there afterwards, and the
// dwarf's one, had output normals turned against their input normals
// (cos -0.92 and -0.69, the input normals within 22° of the true ones),
// so their sink carried them outward, to 0.0070 and 0.0091 above the
// surface: hence the turn test, read against the neighbors' output normals
// (which need no input normals, and trust none that a file got wrong).
// Sinking along m_i rather than leaving the point in place: sydney's Dmax
// 1.34 → 1.25 × (in place 1.21 ×, along the input normal 1.11 ×), residual
// texture at or below the depth limit alone (in place: up to +0.48%),
// normal error within 0.13% of it (along the input normal: up to +1.0%).
//
// Why: on scales packed edge to edge (synth's dense scales, 46-84% of the
// points labelled texture on the models measured), Eq. 2's planes and
// quadrics run through the cells' tops, which count as surface and are
// anchored; the gaps between cells are the texture, and the update lifts
// them to the tops. The output then sits on the envelope of the tops, about
// the texture height above the underlying surface everywhere (the median
// point 0.0039-0.0043 above it where the scales are 0.005 high, on 15
// unseen models and the real suite's bull, bench/quality_real_notes.md,
// session 31), and every point the update carried past the tops adds to
// that offset: Dmax 1.2-2 × the input's on 13 of those 16. Read from the
// moves, the relief leans engraved (-0.61 to -0.98), as sparse grooves do,
// but sparse grooves leave at most 40% of the points texture on the same
// models (V grooves 19-40%, U grooves 21-54% and leaning raised).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct LowerRaisedCellsParams {
  /// Lower dense raised cells at all; false leaves the output on the cells'
  /// tops (the paper, and before session 31).
  bool enabled = true;
  /// q1: the quantile of the input's heights below the output around a
  /// point that counts as the cells' feet; in [0, 1].
  double low_quantile = 0.02;
  /// q2: the quantile of the neighbors' q1 heights that the point takes; in
  /// [0, 1]. 0.1 rather than the quartile: at auto mode's smaller r (the
  /// bull: 0.0187 against the rule's 0.0225) fewer neighbors within ρ reach
  /// a gap, and the quartile left the residual texture 14% above the output
  /// on the tops; 0.1, 3% under it (session 31).
  double spread_quantile = 0.1;
  /// The relief counts as raised cells when the lean is at most -min_lean;
  /// in (0, 1]. RemoveTextureParams fills it with
  /// counter_moves.engraved_min_lean.
  double min_lean = 0.5;
  /// ... and the texture points are more than this share of the cloud; in
  /// [0, 1]. RemoveTextureParams fills it with counter_moves.engraved_share.
  double min_share = 0.5;
  /// ρ, the radius both quantiles are read within, in the cloud's units; >
  /// 0. RemoveTextureParams fills it with the solve radius (0.5 r).
  double radius = 0.0;
  /// d: the deepest a point may end below its own input along its normal,
  /// in units of the texture height h; >= 0, 0 turns the limit off (before
  /// session 34). 1.25, as --move-limit: h is Eq. 2's 99th percentile, 0.76-
  /// 0.95 of the relief's true height on the spot check's dense scales, and
  /// at d = 1 the limit held back a third of the points short of the feet
  /// (residual texture up to 32% above no limit on its rod and torus); at
  /// 1.25 it was at or below no limit on all 15 dense scales, at 1.5 above
  /// it on 4 (session 34, bench/quality_real_notes.md).
  double max_depth = 1.25;
  /// h, the texture height in the cloud's units; >= 0, 0 turns the limit
  /// off. RemoveTextureParams fills it with the 99th percentile of Eq. 2's
  /// heights over the texture points (RemoveTextureReport::texture_height).
  double height = 0.0;
  /// A point whose output normal is more than this many degrees from the
  /// mean output normal of its neighbors within ρ sinks along that mean; in
  /// (0, 180], 180 turns the test off (before session 34).
  double max_turn_deg = 90.0;
};

struct LowerRaisedCellsResult {
  Positions positions;      ///< #P by 3
  bool applied = false;     ///< the relief was read as dense raised cells
  std::size_t lowered = 0;  ///< points moved (c_i < 0 and t_i - d h < 0)
  std::size_t limited = 0;  ///< points the depth limit held above c_i
  std::size_t turned = 0;   ///< points that sank along their neighbors' mean normal
};

void validate(const LowerRaisedCellsParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// normals  #P by 3 unit output normals n, oriented (outward)
/// is_texture  #P Eq. 2 labels (for the share)
/// lean  the relief's lean (LimitCounterMovesResult::lean)
/// R  the neighborhoods; only neighbors within ρ count
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
LowerRaisedCellsResult lower_raised_cells(const Positions& P, const Positions& updated,
                                          const Normals& normals,
                                          const std::vector<std::uint8_t>& is_texture,
                                          double lean, const Neighborhoods& R,
                                          const LowerRaisedCellsParams& params);

}  // namespace detexture
