#include "detexture/pipeline/limit_sink_moves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace detexture {
namespace {

// A 5 x 5 grid of spacing 1 on z = 0 about the centre (point 12), normals
// +z, every point 0.1 from its fitted surface (η); point 13, beside the
// centre, raised by `rise` (the relief rising above it, or a junction's
// other wall). λ = 0.1, depth 2 (0.2), slack 3 (0.3), ρ = 1.5: the
// centre's neighbors are the 8 around it.
struct Grid {
  Positions P;
  Normals N;
  std::vector<float> height = std::vector<float>(25, 0.1f);
  Neighborhoods R;
};

Grid grid(double rise, double search_radius = 1.5) {
  Grid g;
  g.P = Positions::Zero(25, 3);
  for (int i = 0; i < 25; ++i) g.P.row(i) << i % 5 - 2, i / 5 - 2, 0.0;
  g.P(13, 2) = rise;
  g.N = Normals::Zero(25, 3);
  g.N.col(2).setOnes();
  g.R = radius_neighborhoods(g.P, {search_radius, 0});
  return g;
}

LimitSinkMovesParams params(double radius = 1.5) {
  LimitSinkMovesParams p;
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

// With point 13 0.5 above it, the centre sunk by 1 stops at its own height
// 0.1 plus the slack 0.3 below its input; the sideways move stays.
TEST(LimitSinkMoves, APointReliefRisesAboveSinksNoDeeperThanItsHeightPlusTheSlack) {
  const Grid g = grid(0.5);
  const LimitSinkMovesResult r =
      limit_sink_moves(g.P, moved(g.P, 0.05, -1.0), g.N, g.height, g.R, true, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), -0.4, 1e-7);
  EXPECT_EQ(r.positions(12, 0), 0.05);
  EXPECT_EQ(r.positions(12, 1), 0.0);
  for (int i = 0; i < 25; ++i)
    if (i != 12) EXPECT_EQ(r.positions.row(i), g.P.row(i)) << i;
}

// A top (nothing above it) sinks freely, and so does a point whose
// neighbors rise less than depth λ = 0.2 above it (0.15): the nearest model
// may run through the tops of scales, so a top's η says nothing.
TEST(LimitSinkMoves, TopsAndShallowReliefSinkFreely) {
  for (const double rise : {0.0, -0.5, 0.15}) {
    const Grid g = grid(rise);
    const Positions Q = moved(g.P, 0.0, -1.0);
    const LimitSinkMovesResult r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, params());
    EXPECT_EQ(r.limited, 0u) << rise;
    EXPECT_EQ(r.positions, Q) << rise;
  }
}

// Sinks within η + s λ, and rises of any length, stay.
TEST(LimitSinkMoves, ShallowSinksAndRisesStay) {
  const Grid g = grid(0.5);
  for (const double dz : {-0.39, 2.0}) {
    const Positions Q = moved(g.P, 0.0, dz);
    const LimitSinkMovesResult r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, params());
    EXPECT_EQ(r.limited, 0u) << dz;
    EXPECT_EQ(r.positions, Q) << dz;
  }
}

// A taller fitted height lets the point sink farther: η 0.5 stops it at 0.8.
TEST(LimitSinkMoves, TheLimitIsThePointsOwnHeight) {
  Grid g = grid(0.5);
  g.height[12] = 0.5f;
  const LimitSinkMovesResult r =
      limit_sink_moves(g.P, moved(g.P, 0.0, -1.0), g.N, g.height, g.R, true, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), -0.8, 1e-7);
}

// The texture height h is a floor under the limit: with h 0.6 the centre
// (η 0.1, η + s λ 0.4) sinks to 0.6, with η 0.5 (0.8) to 0.8.
TEST(LimitSinkMoves, ThePointSinksAtLeastTheTextureHeight) {
  Grid g = grid(0.5);
  LimitSinkMovesParams p = params();
  p.height = 0.6;
  const Positions Q = moved(g.P, 0.0, -1.0);
  LimitSinkMovesResult r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, p);
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), -0.6, 1e-12);
  g.height[12] = 0.5f;
  r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, p);
  EXPECT_NEAR(r.positions(12, 2), -0.8, 1e-7);
  // A sink within the floor stays.
  const Positions shallow = moved(g.P, 0.0, -0.55);
  g.height[12] = 0.1f;
  r = limit_sink_moves(g.P, shallow, g.N, g.height, g.R, true, p);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, shallow);
}

// Inward is -n: with the normals flipped, point 13 at -0.5 rises above the
// centre and a move to z = +1 is the sink.
TEST(LimitSinkMoves, InwardIsAgainstTheNormal) {
  Grid g = grid(-0.5);
  g.N.col(2).setConstant(-1.0);
  const LimitSinkMovesResult r =
      limit_sink_moves(g.P, moved(g.P, 0.0, 1.0), g.N, g.height, g.R, true, params());
  EXPECT_EQ(r.limited, 1u);
  EXPECT_NEAR(r.positions(12, 2), 0.4, 1e-7);
}

// Neighborhoods searched at 3 hold point 14 (at distance 2), raised to 1:
// within ρ = 1.5 it does not count, within ρ = 3 it does.
TEST(LimitSinkMoves, OnlyNeighborsWithinTheRadiusCount) {
  Grid g = grid(0.0, 3.0);
  g.P(14, 2) = 1.0;
  g.R = radius_neighborhoods(g.P, {3.0, 0});
  const Positions Q = moved(g.P, 0.0, -1.0);
  EXPECT_EQ(limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, params(1.5)).limited, 0u);
  EXPECT_NEAR(limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, params(3.0)).positions(12, 2),
              -0.4, 1e-7);
}

// Relief that is not raised (dense scales, waves, engraving), or slack 0:
// unchanged.
TEST(LimitSinkMoves, OnlyUnderRaisedReliefAndSlackZeroTurnsItOff) {
  const Grid g = grid(0.5);
  const Positions Q = moved(g.P, 0.0, -1.0);
  LimitSinkMovesResult r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, false, params());
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, Q);
  LimitSinkMovesParams off = params();
  off.slack = 0.0;
  r = limit_sink_moves(g.P, Q, g.N, g.height, g.R, true, off);
  EXPECT_EQ(r.limited, 0u);
  EXPECT_EQ(r.positions, Q);
}

TEST(LimitSinkMoves, RejectsBadParametersAndSizes) {
  const Grid g = grid(0.5);
  auto with = [](auto change) {
    LimitSinkMovesParams p = params();
    change(p);
    return p;
  };
  for (const LimitSinkMovesParams& p :
       {with([](LimitSinkMovesParams& p) { p.depth = -1.0; }),
        with([](LimitSinkMovesParams& p) { p.slack = -1.0; }),
        with([](LimitSinkMovesParams& p) { p.slack = std::nan(""); }),
        with([](LimitSinkMovesParams& p) { p.height = -0.1; }),
        with([](LimitSinkMovesParams& p) { p.radius = 0.0; }),
        with([](LimitSinkMovesParams& p) { p.lambda = 0.0; })})
    EXPECT_THROW(limit_sink_moves(g.P, g.P, g.N, g.height, g.R, true, p), std::invalid_argument);
  const Positions fewer = g.P.topRows(24);
  EXPECT_THROW(limit_sink_moves(g.P, fewer, g.N, g.height, g.R, true, params()),
               std::invalid_argument);
  const std::vector<float> short_height(24, 0.0f);
  EXPECT_THROW(limit_sink_moves(g.P, g.P, g.N, short_height, g.R, true, params()),
               std::invalid_argument);
  try {
    LimitSinkMovesParams p = params();
    p.slack = -1.0;
    validate(p);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--sink-slack"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace detexture
