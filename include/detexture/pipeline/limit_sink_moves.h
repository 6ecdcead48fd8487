// Moves below a point's own relief (after Sec. 6, session 35): where the
// relief was raised, a point that relief rises above sinks no farther than
// the texture's height, or than its own height above the underlying
// surface fitted to its neighborhood plus a slack where that is more.
//
//   h_ij = (p_j - p_i)·n_i          j ∈ R_i, |p_j - p_i| <= ρ
//   hi_i = max(0, max_j h_ij)       t_i = (p'_i - p_i)·n_i
//   raised relief, hi_i >= d λ:  t_i < -D_i  becomes  -D_i,
//   D_i = max(h, η_i + s λ)         p''_i = p'_i + (t'_i - t_i) n_i
//
// where p are the input positions, p' the updated ones, n the normals the
// update moved along (the filtered normals), h the texture's height (the
// 99th percentile of the texture points' heights above their fitted
// surfaces, remove_texture.h), η_i the distance of p_i from the nearest
// model Eq. 2 fitted to its own R_i (detect_texture.h, TextureDetection::
// height), λ the RANSAC threshold, d = depth and s = slack. The relief is
// raised where limit_counter_moves.h says so (its side +1: the texture
// points' large moves go mostly inward).
//
// Why: removing raised relief takes a point down to the surface under it,
// no deeper than its own height above that surface, which is at most the
// relief's height; a point in a gap between bumps, or in a concave
// junction, is on the surface already. Where the update took such points
// deeper, the filtered normals had rounded the junction and the weakly
// anchored texture followed them: on the real suite's spider (legs
// 0.012-0.02 thick under bumps 0.012 wide, piercing the body), points of a
// leg where it meets the body, labelled texture but lying on the ground
// truth (η 0-0.2 h), sank by 1.2-1.4 h along the filtered normals, which
// made the case's Dmax (1.34 × the input's; bench/quality_real_notes.md,
// session 35). The limit before it, update_positions.h's max_move, is one
// length for the whole cloud (1.25 h + λ), with room for bumps taller than
// the 99th percentile.
//
// Why only points relief rises above (hi_i >= d λ, the tip test's depth
// mirrored, limit_tip_moves.h): a top has nothing above it and must sink
// by its whole height. Why h as well as η: η is the distance to the
// *nearest* model, and a further plane may run through the tops of scales
// or along the steep flank of a dome, so η can be near 0 where a point
// must sink by most of h. With η + s λ alone, the real suite's saddle with
// scales lost +103% residual texture (every point limited) or +1.3% (s = 2,
// with the depth test), and hemispherical domes on a cube kept a third of
// their height (tests/test_remove_texture.cpp). The first model's
// distance alone, which such a plane does not bias, does not do either: at
// the spider's junction it is the other part's surface, 2.8 h away. And
// only under raised relief: the tops of dense scales are their own fitted
// surface and must sink to the cells' feet (lower_raised_cells.h), as the
// crests of waves must sink to their middle; neither leans raised.
#pragma once

#include <cstddef>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct LimitSinkMovesParams {
  /// d: how far the relief must rise above a point within ρ, along its
  /// normal, for the point to be limited, in units of λ; >= 0.
  double depth = 2.0;
  /// s: how far a point may sink below its own height above its fitted
  /// surface, in units of λ; >= 0, 0 turns the limit off (before session
  /// 35).
  double slack = 3.0;
  /// h, the texture height in the cloud's units; >= 0, 0 leaves η + s λ
  /// alone. remove_texture fills it (RemoveTextureReport::texture_height).
  double height = 0.0;
  /// ρ, the radius the relief is read within, in the cloud's units; > 0.
  /// RemoveTextureParams fills it with the solve radius (0.5 r).
  double radius = 0.0;
  /// λ in the cloud's units; > 0. RemoveTextureParams fills it.
  double lambda = 0.0;
};

struct LimitSinkMovesResult {
  Positions positions;      ///< #P by 3
  std::size_t limited = 0;  ///< points whose move was cut
};

void validate(const LimitSinkMovesParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// normals  #P by 3 unit normals n the update moved along (oriented:
///   inward is -n)
/// surface_height  #P distances η of each input point from its own fitted
///   surface (TextureDetection::height), >= 0
/// R  the neighborhoods; only neighbors within ρ count
/// raised  whether the relief was raised (limit_counter_moves' side +1);
///   false returns the updated positions unchanged
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
LimitSinkMovesResult limit_sink_moves(const Positions& P, const Positions& updated,
                                      const Normals& normals,
                                      const std::vector<float>& surface_height,
                                      const Neighborhoods& R, bool raised,
                                      const LimitSinkMovesParams& params);

}  // namespace detexture
