#include "detexture/pipeline/limit_counter_moves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

// The tests below work their numbers out at l = 0.25 (session 19's limit).
LimitCounterMovesParams with_height(double height) {
  LimitCounterMovesParams p;
  p.height = height;
  p.limit = 0.25;
  return p;
}

// Twenty points on z = 0 with normals +z. The first ten are texture; their
// moves along the normal are `texture_move`. Point 10 moves by 0.8, point 11
// by 0.1, point 12 by -0.8; the rest stay.
struct Moves {
  Positions P, updated;
  Normals N;
  std::vector<std::uint8_t> texture;
};

Moves moves(double texture_move) {
  Moves m;
  m.P = Positions::Zero(20, 3);
  for (int i = 0; i < 20; ++i) m.P(i, 0) = i;
  m.N = Normals::Zero(20, 3);
  m.N.col(2).setOnes();
  m.updated = m.P;
  m.texture.assign(20, 0);
  for (int i = 0; i < 10; ++i) {
    m.texture[i] = 1;
    m.updated(i, 2) = texture_move;
  }
  m.updated(10, 2) = 0.8;
  m.updated(11, 2) = 0.1;
  m.updated(12, 2) = -0.8;
  return m;
}

// Raised relief (every texture point went down by 1, h = 1): the lean is 1,
// and the outward moves saturate at l h = 0.25: 0.8 becomes
// 0.25 tanh(3.2), 0.1 becomes 0.25 tanh(0.4); the inward moves stay. One
// point moved past l h / 2 and is counted.
TEST(LimitCounterMoves, RaisedReliefSaturatesOutwardMovesAtTheLimit) {
  const Moves m = moves(-1.0);
  const LimitCounterMovesResult r =
      limit_counter_moves(m.P, m.updated, m.N, m.texture, with_height(1.0));
  EXPECT_EQ(r.lean, 1.0);
  EXPECT_EQ(r.side, 1);
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(10, 2), 0.25 * std::tanh(3.2), 1e-15);
  EXPECT_LT(r.positions(10, 2), 0.25);
  EXPECT_NEAR(r.positions(11, 2), 0.25 * std::tanh(0.4), 1e-15);
  EXPECT_GT(r.positions(11, 2), 0.09);  // a small move keeps most of its length
  Positions untouched = r.positions;
  untouched(10, 2) = m.updated(10, 2);
  untouched(11, 2) = m.updated(11, 2);
  EXPECT_TRUE(untouched == m.updated);
  // The limit is in units of the height.
  const LimitCounterMovesResult doubled =
      limit_counter_moves(m.P, m.updated * 2.0, m.N, m.texture, with_height(2.0));
  EXPECT_NEAR(doubled.positions(10, 2), 2.0 * r.positions(10, 2), 1e-15);
}

// Session 19's cut: 0.8 becomes exactly 0.25, 0.1 stays.
TEST(LimitCounterMoves, TheHardCutClampsAtTheLimit) {
  const Moves m = moves(-1.0);
  LimitCounterMovesParams p = with_height(1.0);
  p.soft = false;
  const LimitCounterMovesResult r = limit_counter_moves(m.P, m.updated, m.N, m.texture, p);
  EXPECT_EQ(r.limited, 1u);
  Positions expected = m.updated;
  expected(10, 2) = 0.25;
  EXPECT_TRUE(r.positions == expected);
}

// The cut is along the normal the update moved along, whatever its direction.
TEST(LimitCounterMoves, TheCutIsAlongTheNormal) {
  Moves m = moves(-1.0);
  const Eigen::RowVector3d n = Eigen::RowVector3d(1.0, 2.0, 2.0) / 3.0;
  for (int i = 0; i < 20; ++i) {
    m.N.row(i) = n;
    m.updated.row(i) = m.P.row(i) + m.updated(i, 2) * n;
  }
  LimitCounterMovesParams p = with_height(1.0);
  p.soft = false;
  const LimitCounterMovesResult r = limit_counter_moves(m.P, m.updated, m.N, m.texture, p);
  EXPECT_EQ(r.limited, 1u);
  EXPECT_TRUE(r.positions.row(10).isApprox(m.P.row(10) + 0.25 * n, 1e-12));
}

// Engraved relief (the texture went up): inward moves are limited where the
// texture points are at most engraved_share of the cloud (10 of 20 here),
// not where they are more (13 of 20, as on dense scales).
TEST(LimitCounterMoves, EngravedReliefIsLimitedWhereTheTextureIsSparse) {
  Moves m = moves(1.0);
  LimitCounterMovesParams p = with_height(1.0);
  p.soft = false;
  const LimitCounterMovesResult sparse = limit_counter_moves(m.P, m.updated, m.N, m.texture, p);
  EXPECT_EQ(sparse.lean, -1.0);
  EXPECT_EQ(sparse.side, -1);
  EXPECT_EQ(sparse.limited, 1u);
  Positions expected = m.updated;
  expected(12, 2) = -0.25;
  EXPECT_TRUE(sparse.positions == expected);

  p.engraved_share = 0.0;  // never (session 19)
  LimitCounterMovesResult r = limit_counter_moves(m.P, m.updated, m.N, m.texture, p);
  EXPECT_EQ(r.side, 0);
  EXPECT_TRUE(r.positions == m.updated);

  for (int i = 13; i < 16; ++i) m.texture[i] = 1;  // 13 of 20 texture, unmoved
  p.engraved_share = 0.5;
  r = limit_counter_moves(m.P, m.updated, m.N, m.texture, p);
  EXPECT_EQ(r.lean, -1.0);
  EXPECT_EQ(r.side, 0);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_TRUE(r.positions == m.updated);
  p.engraved_share = 1.0;  // always
  EXPECT_EQ(limit_counter_moves(m.P, m.updated, m.N, m.texture, p).side, -1);
  // The engraved side needs a clearer lean than the raised one: 7 texture
  // points up and 3 down lean -0.4, short of 0.5 ...
  Moves mixed = moves(1.0);
  for (int i = 0; i < 3; ++i) mixed.updated(i, 2) = -1.0;
  p = with_height(1.0);
  r = limit_counter_moves(mixed.P, mixed.updated, mixed.N, mixed.texture, p);
  EXPECT_DOUBLE_EQ(r.lean, -0.4);
  EXPECT_EQ(r.side, 0);
  // ... and past 0.35.
  p.engraved_min_lean = 0.35;
  EXPECT_EQ(limit_counter_moves(mixed.P, mixed.updated, mixed.N, mixed.texture, p).side, -1);
  // Raised relief is limited whatever the share.
  Moves raised = moves(-1.0);
  raised.texture.assign(20, 1);
  EXPECT_EQ(
      limit_counter_moves(raised.P, raised.updated, raised.N, raised.texture, with_height(1.0))
          .side,
      1);
}

// A lean below min_lean (waves: as many texture points up as down), or no
// texture move beyond count_from, or the limit off, changes nothing.
TEST(LimitCounterMoves, NoClearSideChangesNothing) {
  Moves m = moves(-1.0);
  for (int i = 0; i < 5; ++i) m.updated(i, 2) = 1.0;  // 5 down, 5 up
  LimitCounterMovesResult r = limit_counter_moves(m.P, m.updated, m.N, m.texture, with_height(1.0));
  EXPECT_EQ(r.lean, 0.0);
  EXPECT_EQ(r.side, 0);
  EXPECT_TRUE(r.positions == m.updated);
  // 7 down, 3 up: lean 0.4 is past 0.35 ...
  for (int i = 0; i < 2; ++i) m.updated(i, 2) = -1.0;
  r = limit_counter_moves(m.P, m.updated, m.N, m.texture, with_height(1.0));
  EXPECT_DOUBLE_EQ(r.lean, 0.4);
  EXPECT_EQ(r.side, 1);
  // ... and short of 0.5.
  LimitCounterMovesParams p = with_height(1.0);
  p.min_lean = 0.5;
  EXPECT_EQ(limit_counter_moves(m.P, m.updated, m.N, m.texture, p).side, 0);

  const Moves small = moves(-0.4);  // below count_from × h = 0.5: no lean
  r = limit_counter_moves(small.P, small.updated, small.N, small.texture, with_height(1.0));
  EXPECT_EQ(r.lean, 0.0);
  EXPECT_EQ(r.side, 0);
  EXPECT_TRUE(r.positions == small.updated);

  const Moves raised = moves(-1.0);
  p = with_height(1.0);
  p.limit = 0.0;
  EXPECT_TRUE(
      limit_counter_moves(raised.P, raised.updated, raised.N, raised.texture, p).positions ==
      raised.updated);
  EXPECT_TRUE(
      limit_counter_moves(raised.P, raised.updated, raised.N, raised.texture, with_height(0.0))
          .positions == raised.updated);
}

// The waves pass (session 27): points whose anchors it released keep their
// outward moves under raised relief; the others are limited as before.
// Point 10 (up by 0.8) is released, point 11 (up by 0.1) is not.
TEST(LimitCounterMoves, ReleasedPointsKeepTheirOutwardMoves) {
  const Moves m = moves(-1.0);
  std::vector<std::uint8_t> released(20, 0);
  released[10] = 1;
  LimitCounterMovesParams p = with_height(1.0);
  const LimitCounterMovesResult r =
      limit_counter_moves(m.P, m.updated, m.N, m.texture, p, released);
  EXPECT_EQ(r.side, 1);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions(10, 2), 0.8);
  EXPECT_NEAR(r.positions(11, 2), 0.25 * std::tanh(0.4), 1e-15);
  // Off: released points are limited like the others (before session 27).
  p.free_released = false;
  const LimitCounterMovesResult all =
      limit_counter_moves(m.P, m.updated, m.N, m.texture, p, released);
  EXPECT_EQ(all.limited, 1u);
  EXPECT_NEAR(all.positions(10, 2), 0.25 * std::tanh(3.2), 1e-15);
  // Engraved relief: a released point's inward move is limited as before.
  const Moves up = moves(1.0);
  released.assign(20, 0);
  released[12] = 1;  // down by 0.8
  p = with_height(1.0);
  p.soft = false;
  const LimitCounterMovesResult engraved =
      limit_counter_moves(up.P, up.updated, up.N, up.texture, p, released);
  EXPECT_EQ(engraved.side, -1);
  EXPECT_EQ(engraved.positions(12, 2), -0.25);
}

// With released points the relief counts as raised from released_min_lean
// (0.5), not min_lean (0.35): 7 texture points down and 3 up lean 0.4.
TEST(LimitCounterMoves, TheWavesPassAsksForAClearerLean) {
  Moves m = moves(-1.0);
  for (int i = 0; i < 3; ++i) m.updated(i, 2) = 1.0;
  const std::vector<std::uint8_t> none_released(20, 0);
  LimitCounterMovesParams p = with_height(1.0);
  EXPECT_EQ(limit_counter_moves(m.P, m.updated, m.N, m.texture, p).side, 1);
  const LimitCounterMovesResult r =
      limit_counter_moves(m.P, m.updated, m.N, m.texture, p, none_released);
  EXPECT_DOUBLE_EQ(r.lean, 0.4);
  EXPECT_EQ(r.side, 0);
  EXPECT_TRUE(r.positions == m.updated);
  p.released_min_lean = 0.4;
  EXPECT_EQ(limit_counter_moves(m.P, m.updated, m.N, m.texture, p, none_released).side, 1);
}

TEST(LimitCounterMoves, BadInputIsRefused) {
  const Moves m = moves(-1.0);
  LimitCounterMovesParams p = with_height(1.0);
  p.limit = -0.1;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p = with_height(1.0);
  p.min_lean = 0.0;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.min_lean = 1.5;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p = with_height(-1.0);
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p = with_height(1.0);
  p.engraved_min_lean = 0.0;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.engraved_min_lean = 1.5;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p = with_height(1.0);
  p.engraved_share = -0.1;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.engraved_share = 1.5;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.engraved_share = std::nan("");
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p = with_height(1.0);
  p.released_min_lean = 0.0;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.released_min_lean = 1.5;
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  p.released_min_lean = std::nan("");
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, with_height(1.0),
                                   std::vector<std::uint8_t>(3, 0)),
               std::invalid_argument);
  p = with_height(1.0);
  p.count_from = std::nan("");
  EXPECT_THROW(limit_counter_moves(m.P, m.updated, m.N, m.texture, p), std::invalid_argument);
  EXPECT_THROW(limit_counter_moves(m.P, m.updated.topRows(5), m.N, m.texture, with_height(1.0)),
               std::invalid_argument);
  EXPECT_THROW(
      limit_counter_moves(m.P, m.updated, m.N, std::vector<std::uint8_t>(3, 0), with_height(1.0)),
      std::invalid_argument);
}

// Through remove_texture: a plane with 25 raised bumps and one dent of the
// same size between them. The bumps' points go down, so the relief leans
// raised and no point rises by more than l (0.125) of the texture height:
// the dent, a minority feature, is filled by that much only (the price of
// the limit, README's known limits). With the limit off it is filled.
TEST(LimitCounterMoves, RemoveTextureCutsRisesUnderRaisedRelief) {
  const int side = 61;
  const double amplitude = 0.03, width = 0.03;
  Positions P(side * side, 3);
  int dent = 0;
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const int i = a * side + b;
      const double x = a / (side - 1.0), y = b / (side - 1.0);
      const double du = x - (std::floor(x / 0.2) + 0.5) * 0.2;
      const double dv = y - (std::floor(y / 0.2) + 0.5) * 0.2;
      const double dd = (x - 0.6) * (x - 0.6) + (y - 0.6) * (y - 0.6);
      if (dd < 1e-12) dent = i;
      P.row(i) << x, y,
          amplitude * (std::exp(-(du * du + dv * dv) / (2 * width * width)) -
                       std::exp(-dd / (2 * width * width)));
    }
  Normals N = Normals::Zero(P.rows(), 3);
  N.col(2).setOnes();
  RemoveTextureParams p;
  p.radius = Length{0.1, Length::Unit::Absolute};
  p.threads = 2;
  const RemoveTextureResult limited = remove_texture(P, N, p);
  p.counter_moves.limit = 0.0;
  const RemoveTextureResult free = remove_texture(P, N, p);
  const double h = limited.report.texture_height;
  EXPECT_GT(h, 0.5 * amplitude);
  EXPECT_GE(limited.report.relief_lean, 0.35);
  EXPECT_GT(limited.report.counter_moves_limited, 0u);
  EXPECT_EQ(free.report.counter_moves_limited, 0u);
  const double rise_limited = (limited.positions.col(2) - P.col(2)).maxCoeff();
  const double rise_free = (free.positions.col(2) - P.col(2)).maxCoeff();
  EXPECT_LE(rise_limited, RemoveTextureParams().counter_moves.limit * h + 1e-12);
  EXPECT_GT(rise_free, 0.5 * h);
  EXPECT_LT(limited.positions(dent, 2), -0.5 * amplitude);
  EXPECT_GT(free.positions(dent, 2), -0.25 * amplitude);
}

// Through remove_texture, the waves pass: synth's torus with dense waves
// (0.04 wide, 0.016 high, 30k points; r = 1.5 × 0.04) runs the update again
// with the anchors of its flagged points lowered. With both leans lowered so
// that both passes limit, the released points keep their outward moves:
// fewer points are limited than with free_released off, and the outputs
// differ. At the default leans the second pass's lean (about 0.33) limits
// nothing either way.
TEST(LimitCounterMoves, RemoveTextureFreesThePointsTheWavesPassReleased) {
  const SynthesizedShape torus = test::wavy_torus();
  RemoveTextureParams p = test::wavy_torus_params();
  p.counter_moves.min_lean = 0.01;
  p.counter_moves.released_min_lean = 0.01;
  const RemoveTextureResult freed = remove_texture(torus.positions, torus.normals, p);
  p.counter_moves.free_released = false;
  const RemoveTextureResult all = remove_texture(torus.positions, torus.normals, p);
  ASSERT_GT(freed.report.waves_released, 0u);
  EXPECT_GE(freed.report.relief_lean, 0.01);
  EXPECT_GT(freed.report.counter_moves_limited, 0u);
  EXPECT_LT(freed.report.counter_moves_limited, all.report.counter_moves_limited);
  EXPECT_FALSE(freed.positions == all.positions);
  p = test::wavy_torus_params();
  const RemoveTextureResult plain = remove_texture(torus.positions, torus.normals, p);
  EXPECT_LT(plain.report.relief_lean, p.counter_moves.released_min_lean);
  EXPECT_EQ(plain.report.counter_moves_limited, 0u);
}

}  // namespace
}  // namespace detexture
