#include "detexture/pipeline/limit_tip_moves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace detexture {
namespace {

// A 5 x 5 grid of spacing 1 about the centre (point 12), z = -slope × the
// distance from the centre (a cone; slope < 0 turns it into a pit), normals
// +z. λ = 0.1, depth 2 (0.2), slack 1 (0.1), ρ = 1.5: the centre's neighbors
// are the 8 around it (at 1 and √2), the lowest at -slope √2.
struct Cone {
  Positions P;
  Normals N;
  Neighborhoods R;
};

Cone cone(double slope, double search_radius = 1.5) {
  Cone c;
  c.P.resize(25, 3);
  for (int i = 0; i < 25; ++i) {
    const double x = i % 5 - 2, y = i / 5 - 2;
    c.P.row(i) << x, y, -slope * std::sqrt(x * x + y * y);
  }
  c.N = Normals::Zero(25, 3);
  c.N.col(2).setOnes();
  c.R = radius_neighborhoods(c.P, {search_radius, 0});
  return c;
}

LimitTipMovesParams params(double radius = 1.5) {
  LimitTipMovesParams p;
  p.radius = radius;
  p.lambda = 0.1;
  return p;
}

// The centre moved by (dx, 0, dz); every other point stays.
Positions moved(const Positions& P, double dx, double dz) {
  Positions Q = P;
  Q(12, 0) += dx;
  Q(12, 2) += dz;
  return Q;
}

// The cone's top (hi 0, lo -0.5 √2 <= -0.2) moved out by 0.3 ends at its
// highest neighbor (itself, 0) plus the slack 0.1; the sideways move stays.
TEST(LimitTipMoves, APeakRisesNoFartherThanItsReliefPlusTheSlack) {
  const Cone c = cone(0.5);
  const LimitTipMovesResult r = limit_tip_moves(c.P, moved(c.P, 0.05, 0.3), c.N, c.R, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), 0.1, 1e-15);
  EXPECT_EQ(r.positions(12, 0), 0.05);
  EXPECT_EQ(r.positions(12, 1), 0.0);
  for (int i = 0; i < 25; ++i)
    if (i != 12) EXPECT_EQ(r.positions.row(i), c.P.row(i)) << i;
}

// Removing a bump moves its top inward by any amount.
TEST(LimitTipMoves, APeakSinksFreely) {
  const Cone c = cone(0.5);
  const Positions Q = moved(c.P, 0.0, -0.3);
  const LimitTipMovesResult r = limit_tip_moves(c.P, Q, c.N, c.R, params());
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, Q);
}

// Upside down: a groove's bottom sinks at most 0.1 below its lowest
// neighbor (itself) and rises freely.
TEST(LimitTipMoves, APitSinksNoFartherAndRisesFreely) {
  const Cone c = cone(-0.5);
  const LimitTipMovesResult in = limit_tip_moves(c.P, moved(c.P, 0.0, -0.3), c.N, c.R, params());
  EXPECT_EQ(in.limited, 1u);
  EXPECT_NEAR(in.positions(12, 2), -0.1, 1e-15);
  const Positions Q = moved(c.P, 0.0, 0.3);
  const LimitTipMovesResult out = limit_tip_moves(c.P, Q, c.N, c.R, params());
  EXPECT_EQ(out.limited, 0u);
  EXPECT_EQ(out.positions, Q);
}

// The tests read heights along the normal, so unoriented normals give the
// same answer: with -z the top is a pit whose outward is -z.
TEST(LimitTipMoves, TheNormalsSignDoesNotMatter) {
  Cone c = cone(0.5);
  c.N.col(2).setConstant(-1.0);
  const LimitTipMovesResult r = limit_tip_moves(c.P, moved(c.P, 0.0, 0.3), c.N, c.R, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), 0.1, 1e-15);
}

// Relief shallower than depth λ (the lowest neighbor 0.1 √2 = 0.14 below,
// under 0.2) and flat surface are no tips: nothing is cut.
TEST(LimitTipMoves, ShallowReliefAndFlatSurfaceAreNoTips) {
  for (const double slope : {0.1, 0.0}) {
    const Cone c = cone(slope);
    const Positions Q = moved(c.P, 0.0, 0.3);
    const LimitTipMovesResult r = limit_tip_moves(c.P, Q, c.N, c.R, params());
    EXPECT_EQ(r.limited, 0u) << slope;
    EXPECT_EQ(r.positions, Q) << slope;
  }
}

// A neighbor 0.05 above the top (within the slack) leaves it a peak, and the
// limit is that neighbor's height plus the slack; 0.15 above, it is no peak.
TEST(LimitTipMoves, TheSlackLetsANeighborStandAboveTheTip) {
  Cone c = cone(0.5);
  c.P(13, 2) = 0.05;
  LimitTipMovesResult r = limit_tip_moves(c.P, moved(c.P, 0.0, 0.3), c.N, c.R, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), 0.15, 1e-15);
  c.P(13, 2) = 0.15;
  r = limit_tip_moves(c.P, moved(c.P, 0.0, 0.3), c.N, c.R, params());
  EXPECT_EQ(r.limited, 0u);
  EXPECT_NEAR(r.positions(12, 2), 0.3, 1e-15);
}

// Neighborhoods searched at 3 hold point 14 (at distance 2), raised to 1
// above the top: within ρ = 1.5 it does not count, within ρ = 3 it makes
// the top no peak.
TEST(LimitTipMoves, OnlyNeighborsWithinTheRadiusCount) {
  Cone c = cone(0.5, 3.0);
  c.P(14, 2) = 1.0;
  c.R = radius_neighborhoods(c.P, {3.0, 0});
  const Positions Q = moved(c.P, 0.0, 0.3);
  EXPECT_NEAR(limit_tip_moves(c.P, Q, c.N, c.R, params(1.5)).positions(12, 2), 0.1, 1e-15);
  EXPECT_EQ(limit_tip_moves(c.P, Q, c.N, c.R, params(3.0)).limited, 0u);
}

TEST(LimitTipMoves, DepthZeroTurnsItOff) {
  const Cone c = cone(0.5);
  LimitTipMovesParams p = params();
  p.depth = 0.0;
  const Positions Q = moved(c.P, 0.0, 0.3);
  const LimitTipMovesResult r = limit_tip_moves(c.P, Q, c.N, c.R, p);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, Q);
}

// The ceiling (c = 1, 0.1) on a cone too shallow for a tip (its lowest
// neighbor 0.05 √2 = 0.07 below, under depth λ 0.2; depth 0 gives the same):
// the top lies in the upper half of its relief (hi 0, lo -0.07), so it
// moves out by at most 0.1 and in freely; a move out under 0.1 stays.
TEST(LimitTipMoves, TheCeilingHoldsTheUpperHalfsOutwardMoves) {
  const Cone c = cone(0.05);
  for (const double depth : {2.0, 0.0}) {
    LimitTipMovesParams p = params();
    p.depth = depth;
    ASSERT_EQ(limit_tip_moves(c.P, moved(c.P, 0.0, 0.3), c.N, c.R, p).limited, 0u);
    p.ceiling = 1.0;
    const LimitTipMovesResult out = limit_tip_moves(c.P, moved(c.P, 0.05, 0.3), c.N, c.R, p);
    EXPECT_EQ(out.limited, 1u) << depth;
    EXPECT_NEAR(out.positions(12, 2), 0.1, 1e-15) << depth;
    EXPECT_EQ(out.positions(12, 0), 0.05) << depth;
    for (const double dz : {-0.3, 0.08}) {
      const Positions Q = moved(c.P, 0.0, dz);
      const LimitTipMovesResult free = limit_tip_moves(c.P, Q, c.N, c.R, p);
      EXPECT_EQ(free.limited, 0u) << depth << " " << dz;
      EXPECT_EQ(free.positions, Q) << depth << " " << dz;
    }
  }
}

// Upside down (a shallow pit), the bottom lies in the lower half: it moves
// in by at most 0.1 and out freely. With -z normals on the cone, the top is
// the lower half of its relief, and the answer is the same as with +z.
TEST(LimitTipMoves, TheCeilingHoldsTheLowerHalfsInwardMovesForEitherSign) {
  LimitTipMovesParams p = params();
  p.ceiling = 1.0;
  const Cone pit = cone(-0.05);
  EXPECT_NEAR(limit_tip_moves(pit.P, moved(pit.P, 0.0, -0.3), pit.N, pit.R, p).positions(12, 2),
              -0.1, 1e-15);
  EXPECT_EQ(limit_tip_moves(pit.P, moved(pit.P, 0.0, 0.3), pit.N, pit.R, p).limited, 0u);
  Cone top = cone(0.05);
  top.N.col(2).setConstant(-1.0);
  const LimitTipMovesResult r = limit_tip_moves(top.P, moved(top.P, 0.0, 0.3), top.N, top.R, p);
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), 0.1, 1e-15);
}

// A thin plate: a flat 5 x 5 sheet (normals +z) over a second one 0.5
// below (normals -z). The top sheet's centre has the bottom sheet within
// ρ, but their normals disagree (n_j·n_i = -1 < 0.5): its relief is flat,
// neither half, and its move out stays. Counting every neighbor
// (ceiling_min_cos -1) would put it in the upper half and cut it to 0.1.
// The tips are off (depth 0): they count every neighbor and would make
// the centre a peak.
TEST(LimitTipMoves, TheCeilingIgnoresTheOtherSideOfAThinPart) {
  const Cone sheet = cone(0.0);
  Positions P(50, 3);
  Normals N(50, 3);
  P << sheet.P, sheet.P;
  P.bottomRows(25).col(2).setConstant(-0.5);
  N << sheet.N, -sheet.N;
  const Neighborhoods R = radius_neighborhoods(P, {1.5, 0});
  Positions Q = P;
  Q(12, 2) = 0.3;
  LimitTipMovesParams p = params();
  p.depth = 0.0;
  p.ceiling = 1.0;
  const LimitTipMovesResult r = limit_tip_moves(P, Q, N, R, p);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, Q);
  p.ceiling_min_cos = -1.0;
  EXPECT_NEAR(limit_tip_moves(P, Q, N, R, p).positions(12, 2), 0.1, 1e-15);
}

TEST(LimitTipMoves, RejectsBadParametersAndSizes) {
  const Cone c = cone(0.5);
  auto with = [](auto change) {
    LimitTipMovesParams p = params();
    change(p);
    return p;
  };
  for (const LimitTipMovesParams& p :
       {with([](LimitTipMovesParams& p) { p.depth = -1.0; }),
        with([](LimitTipMovesParams& p) { p.slack = -0.5; }),
        with([](LimitTipMovesParams& p) { p.slack = std::nan(""); }),
        with([](LimitTipMovesParams& p) { p.radius = 0.0; }),
        with([](LimitTipMovesParams& p) { p.lambda = 0.0; }),
        with([](LimitTipMovesParams& p) { p.ceiling = -1.0; }),
        with([](LimitTipMovesParams& p) { p.ceiling = INFINITY; }),
        with([](LimitTipMovesParams& p) { p.ceiling_min_cos = 1.5; })})
    EXPECT_THROW(limit_tip_moves(c.P, c.P, c.N, c.R, p), std::invalid_argument);
  const Positions fewer = c.P.topRows(24);
  EXPECT_THROW(limit_tip_moves(c.P, fewer, c.N, c.R, params()), std::invalid_argument);
  try {
    LimitTipMovesParams p = params();
    p.depth = -1.0;
    validate(p);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--tip-depth"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace detexture
