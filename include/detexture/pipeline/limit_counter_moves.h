// Moves against the relief (after Sec. 6, session 19): where the removed
// texture was raised, no point moves outward by more than a share of the
// texture's height.
//
//   t_i  = (p'_i - p_i)·n_i                       the move along the normal
//   B_in = #{i texture: t_i < -c h},  B_out = #{i texture: t_i > c h}
//   lean = (B_in - B_out) / (B_in + B_out)        in [-1, 1], 0 without moves
//   lean >= min_lean:            p''_i = p'_i - max(t_i - l h, 0) n_i
//   lean <= -min_lean, engraved: p''_i = p'_i - min(t_i + l h, 0) n_i
//
// where p are the input positions, p' the updated ones, n the normals the
// update moved along (the filtered normals), h the texture's height (the
// 99th percentile of the texture points' heights above their fitted
// surfaces, remove_texture.h), c = count_from and l = limit. Every point is
// limited, texture or not.
//
// Why: the update fits the positions to normals that the filters round at
// σs. Where the shape turns concave more tightly than that (an armpit, the
// junction of a leg and a body, the inside of a fold), the rounded normals
// make a fillet that bridges the junction, and the points there are carried
// outward, past the top of the relief, by about the texture's height: this
// is where the output's largest distances from the underlying surface come
// from (Dmax 1.4-2 × the input's on 19 of 30 textured models no suite uses,
// bench/quality_real_notes.md, session 19). When the relief was raised
// (bumps, domes), removing it moves texture points inward, and no point has
// a reason to move outward by more than noise and the sag the anchors
// allow. Which way the relief went is read from the moves themselves: the
// texture points that moved by more than c h go mostly inward under raised
// relief (a lean of 0.39-1.0 on the bumps and domes of 30 unseen models,
// 0.56 on the suite's spider), both ways across waves, noise and the facets
// of organic shapes (-0.2 to 0.25; the person and the duck -0.15). The lean
// is one number for the whole cloud (each tile's, in tiled runs): the points
// at a bridged junction all move outward, so the lean around them says
// nothing. Its price: a dent among raised bumps is filled by l h only.
//
// Engraved relief (the lean at most -min_lean: grooves, and dense scales,
// which the update lifts to their tops) is left alone by default: limiting
// its inward moves fixed the Dmax of V grooves on unseen models but cost
// the suite's scaled cylinder +7.5% in normal error, whose scales' raised
// edges move inward legitimately.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/types.h"

namespace detexture {

struct LimitCounterMovesParams {
  /// l: moves against the relief are cut to this, in units of the texture
  /// height h; >= 0, 0 turns the limit off (before session 19).
  double limit = 0.25;
  /// c: the lean counts the texture points that moved by more than this, in
  /// units of h; >= 0.
  double count_from = 0.5;
  /// The relief's side is taken as known when |lean| reaches this; in (0, 1].
  double min_lean = 0.35;
  /// Also limit inward moves where the relief leans engraved (see above).
  bool engraved = false;
  /// h, the texture height in the cloud's units; >= 0, 0 limits nothing.
  /// remove_texture fills it (RemoveTextureReport::texture_height).
  double height = 0.0;
};

struct LimitCounterMovesResult {
  Positions positions;      ///< #P by 3
  double lean = 0.0;        ///< the lean above (0 when no texture point moved beyond c h)
  int side = 0;             ///< +1 raised (outward moves limited), -1 engraved, 0 none
  std::size_t limited = 0;  ///< points whose move was cut
};

void validate(const LimitCounterMovesParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// normals  #P by 3 unit normals n the update moved along
/// is_texture  #P Eq. 2 labels (the lean reads the texture points' moves)
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
LimitCounterMovesResult limit_counter_moves(const Positions& P, const Positions& updated,
                                            const Normals& normals,
                                            const std::vector<std::uint8_t>& is_texture,
                                            const LimitCounterMovesParams& params);

}  // namespace detexture
