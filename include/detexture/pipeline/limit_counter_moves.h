// Moves against the relief (after Sec. 6, session 19): where the removed
// texture was raised, no point moves outward by more than a share of the
// texture's height.
//
//   t_i  = (p'_i - p_i)·n_i                       the move along the normal
//   B_in = #{i texture: t_i < -c h},  B_out = #{i texture: t_i > c h}
//   lean = (B_in - B_out) / (B_in + B_out)        in [-1, 1], 0 without moves
//   lean >= min_lean (raised):                 t_i > 0 becomes s(t_i)
//   lean <= -e, share <= s_e (engraved):       t_i < 0 becomes -s(-t_i)
//   s(t) = l h tanh(t / (l h))                    p''_i = p'_i + (s - t_i) n_i
//
// where p are the input positions, p' the updated ones, n the normals the
// update moved along (the filtered normals), h the texture's height (the
// 99th percentile of the texture points' heights above their fitted
// surfaces, remove_texture.h), c = count_from, l = limit, share the texture
// points' share of the cloud, e = engraved_min_lean and s_e =
// engraved_share. Every point is limited, texture or not. s saturates at
// l h and is the identity to first order: moves well under l h keep most
// of their length (0.5 l h keeps 92%), and where limited and free points
// meet there is no kink. Session 19 cut at l h (soft = false); against
// that cut the saturation gave -1.0% residual texture and -0.25% normal
// error on 30 unseen dense reliefs (session 20).
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
// Engraved relief is limited only where it leans clearly, by e = 0.5, and
// the texture is sparse, at most s_e of the points (session 20). Sparse
// engraving (V grooves: 13-38% texture on 11 models) has the surface
// between its features, so the side is known, and a floor point carried
// further in by a wall's normal is an error: limiting inward moves there
// took the Dmax of the V grooves on 9 unseen models under 1.25 × the
// input's (5 of them over before), with less normal error on all 9. Dense
// scales (46-80% texture on 12 models) lean engraved too, because the
// update lifts their narrow gaps to the cells' tops, but their cells are
// raised and move inward legitimately: limiting them cost the suite's
// scaled cylinder (62%) +7.5% in normal error (bench/quality_real_notes.md,
// sessions 19-20). The clearer lean: organic structure smaller than r,
// filled where it is concave, moves outward too, so raised relief on such
// shapes can lean engraved: the person with bumps leans -0.15 as a cloud
// and -0.42 as the mesh suite's mesh (40% texture), where limiting its
// inward moves left +6.8% residual texture; the V grooves lean -0.36 to
// -1.0 (only the AT-AT's, at -0.36, is left out).
//
// The waves pass and l = 0.125 (session 27). Where the update ran a second
// time with the anchors of the surface points flagged as lying on waves
// lowered (remove_texture.h, wave_share_low), those points are released to
// follow the filtered normals, and under raised relief their outward moves
// are left as they are: the pass is there to fill the troughs between
// waves or grooves, which are outward moves, and cutting them undid it (U
// grooves whose update lowers the ridges between them read as raised, a
// lean of 0.44-0.99 on five unseen models, and kept +3-4% residual texture,
// session 19's known cost). The pass's lean is read from moves the released
// anchors made both ways, and sits lower and less steady than the first
// pass's (the torus with waves: 0.45 in the first pass, 0.34-0.37 in the
// second, either side of min_lean as the first pass changed), so the pass
// counts the relief as raised only from released_min_lean = 0.5. With the
// pass steady, outward moves saturate at an eighth of the texture height (l
// = 0.125) instead of a quarter. Quick runs of 114 cases (both suites and the 96 unseen cases,
// bench/quality_real_notes.md, session 27), geometric means of normal error
// / residual texture: the spot check's 30 dense reliefs -0.7% / -1.9%
// (domes -1% to -5% in normal error), its 30 waves and grooves -0.1% /
// -0.2%, the broad check's 36 -0.3% / -0.9%, the real suite +0.1% / -0.6%,
// bench/quality -0.04% / +0.01%; the worst case the axe's U grooves +1.9% /
// +2.3%, the spider +0.8% / -4.8%; Dmax over 1.25 × the input's in as many
// cases. Each part alone: the released points free, -1.0% to -3.4%
// residual on the five U grooves and no case worse; l = 0.125 alone, the
// torus with waves +32% residual (its second pass then leaned 0.37 and was
// limited); without the clearer lean, +9%; the raised limit off in the
// whole second pass, the faerie's bumps +3.3% / +9.2%; the first pass's
// side kept for the second, the torus +27%; l = 0.5, +1.4% / +2.1% on the
// dense reliefs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/types.h"

namespace detexture {

struct LimitCounterMovesParams {
  /// l: moves against the relief are cut to this, in units of the texture
  /// height h; >= 0, 0 turns the limit off (before session 19). 0.125 since
  /// session 27 (0.25 before; see above).
  double limit = 0.125;
  /// c: the lean counts the texture points that moved by more than this, in
  /// units of h; >= 0.
  double count_from = 0.5;
  /// The relief counts as raised when the lean reaches this; in (0, 1].
  double min_lean = 0.35;
  /// s_e: inward moves are limited where the relief leans engraved only if
  /// the texture points are at most this share of the cloud (see above); in
  /// [0, 1], 0 never (session 19), 1 whenever it leans engraved.
  double engraved_share = 0.5;
  /// e: the lean at which relief counts as engraved (it must be <= -e);
  /// in (0, 1].
  double engraved_min_lean = 0.5;
  /// Saturate moves against the relief smoothly (s above); false cuts them
  /// at l h (session 19).
  bool soft = true;
  /// h, the texture height in the cloud's units; >= 0, 0 limits nothing.
  /// remove_texture fills it (RemoveTextureReport::texture_height).
  double height = 0.0;
  /// Leave the outward moves of released points (see above) as they are under
  /// raised relief; false limits them like the others (before session 27).
  bool free_released = true;
  /// With released points (the waves pass), the relief counts as raised from
  /// this lean instead of min_lean (see above); in (0, 1].
  double released_min_lean = 0.5;
};

struct LimitCounterMovesResult {
  Positions positions;  ///< #P by 3
  /// the lean above (0 when no texture point moved beyond c h or h is 0;
  /// read with l = 0 too, for lower_raised_cells.h)
  double lean = 0.0;
  int side = 0;         ///< +1 raised (outward moves limited), -1 engraved, 0 none
  /// points that moved against the relief by more than l h / 2 (soft: cut
  /// by 7.6% or more), or by more than l h (the cut at l h)
  std::size_t limited = 0;
};

void validate(const LimitCounterMovesParams& params);

/// P  #P by 3 input positions p
/// updated  #P by 3 updated positions p'
/// normals  #P by 3 unit normals n the update moved along
/// is_texture  #P Eq. 2 labels (the lean reads the texture points' moves)
/// released  #P (1 = the update released the point's anchor; see above), or
///   empty for none
/// Throws std::invalid_argument on bad parameters or mismatched sizes.
/// Deterministic for any thread count.
LimitCounterMovesResult limit_counter_moves(const Positions& P, const Positions& updated,
                                            const Normals& normals,
                                            const std::vector<std::uint8_t>& is_texture,
                                            const LimitCounterMovesParams& params,
                                            const std::vector<std::uint8_t>& released = {});

}  // namespace detexture
