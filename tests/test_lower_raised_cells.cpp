#include "detexture/pipeline/lower_raised_cells.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"

namespace detexture {
namespace {

// A 21 x 21 grid of spacing 1 on z = 0 (the cells' feet), normals +z, with
// every third row and column a gap and the rest cells: the input has the
// cells at z = h and the gaps at 0, and the update left every point at h (on
// the cells' tops). 8 of 9 points are cells, so the texture labels mark 5 of
// 9 (any share over 0.5 will do). ρ = 2.5: 21 neighbors at most, at least 5
// of them gaps, so every 2% quantile is a gap.
struct Cells {
  Positions P, updated;
  Normals N;
  std::vector<std::uint8_t> is_texture;
  Neighborhoods R;
};

constexpr double kHeight = 0.3;

Cells cells() {
  Cells c;
  c.P.resize(441, 3);
  c.updated.resize(441, 3);
  c.is_texture.assign(441, 0);
  for (int i = 0; i < 441; ++i) {
    const int x = i % 21, y = i / 21;
    const bool gap = x % 3 == 0 || y % 3 == 0;
    c.P.row(i) << x, y, gap ? 0.0 : kHeight;
    c.updated.row(i) << x, y, kHeight;
    c.is_texture[i] = i % 9 < 5;
  }
  c.N = Normals::Zero(441, 3);
  c.N.col(2).setOnes();
  c.R = radius_neighborhoods(c.P, {2.5, 0});
  return c;
}

LowerRaisedCellsParams params() {
  LowerRaisedCellsParams p;
  p.radius = 2.5;
  p.height = kHeight;
  return p;
}

TEST(LowerRaisedCells, TheOutputOnTheCellsTopsSinksToTheirFeet) {
  const Cells c = cells();
  const LowerRaisedCellsResult r =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, params());
  EXPECT_TRUE(r.applied);
  EXPECT_EQ(r.lowered, 441u);
  for (int i = 0; i < 441; ++i) {
    EXPECT_NEAR(r.positions(i, 2), 0.0, 1e-15) << i;
    EXPECT_EQ(r.positions(i, 0), c.updated(i, 0));
    EXPECT_EQ(r.positions(i, 1), c.updated(i, 1));
  }
}

// Raised relief (a positive lean), too little texture for dense cells, or
// the option off: nothing moves.
TEST(LowerRaisedCells, OnlyDenseReliefLeaningEngravedIsLowered) {
  const Cells c = cells();
  for (const double lean : {0.8, 0.0, -0.49}) {
    const LowerRaisedCellsResult r =
        lower_raised_cells(c.P, c.updated, c.N, c.is_texture, lean, c.R, params());
    EXPECT_FALSE(r.applied) << lean;
    EXPECT_EQ(r.lowered, 0u);
    EXPECT_EQ(r.positions, c.updated);
  }
  std::vector<std::uint8_t> sparse(441, 0);
  for (int i = 0; i < 220; ++i) sparse[i] = 1;  // 220 of 441: under half
  EXPECT_FALSE(lower_raised_cells(c.P, c.updated, c.N, sparse, -0.8, c.R, params()).applied);
  LowerRaisedCellsParams off = params();
  off.enabled = false;
  EXPECT_EQ(lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, off).positions,
            c.updated);
}

// Where the update moved nothing, or moved the input inward (raised relief
// removed), nothing sinks: only the input below the output counts.
TEST(LowerRaisedCells, NoPointSinksBelowAnInputThatLiesAboveIt) {
  Cells c = cells();
  c.updated = c.P;
  c.updated.col(2).setConstant(-0.1);  // every point moved in
  const LowerRaisedCellsResult r =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, params());
  EXPECT_TRUE(r.applied);
  EXPECT_EQ(r.lowered, 0u);
  EXPECT_EQ(r.positions, c.updated);
}

// Each input point is read from its own output point, along its own normal:
// on a sphere of radius 1 whose output lies 0.05 outside it everywhere, every
// point goes back to the sphere exactly, with no sag from the curvature.
TEST(LowerRaisedCells, ACurvedSurfaceAddsNoSag) {
  const int n = 2000;
  Positions P(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, rho = std::sqrt(1.0 - z * z);
    P.row(i) << rho * std::cos(golden * i), rho * std::sin(golden * i), z;
  }
  const Normals N = P;
  const Positions updated = P * 1.05;
  const std::vector<std::uint8_t> texture(n, 1);
  LowerRaisedCellsParams p;
  p.radius = 0.2;
  const Neighborhoods R = radius_neighborhoods(P, {0.2, 0});
  const LowerRaisedCellsResult r = lower_raised_cells(P, updated, N, texture, -1.0, R, p);
  ASSERT_EQ(r.lowered, static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) EXPECT_NEAR(r.positions.row(i).norm(), 1.0, 1e-12) << i;
}

// The depth limit (max_depth d, height h): every cell's output sits on its
// input (t = 0) and sinks by the full c = -h to the feet at z = 0, within the
// default d h below it, so the limit holds nothing back. At d = 0.5 each cell
// stops at -h/2, half a height below its input; a gap's input lies h below
// its output (t = -h), so it may sink 1.5 h and reaches the feet. d = 0 or
// h = 0 turns the limit off.
TEST(LowerRaisedCells, NoPointEndsMoreThanTheDepthLimitBelowItsInput) {
  const Cells c = cells();
  const LowerRaisedCellsResult full =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, params());
  EXPECT_EQ(full.limited, 0u);
  LowerRaisedCellsParams half = params();
  half.max_depth = 0.5;
  const LowerRaisedCellsResult r =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, half);
  std::size_t cells_count = 0;
  for (int i = 0; i < 441; ++i) {
    const bool gap = (i % 21) % 3 == 0 || (i / 21) % 3 == 0;
    cells_count += !gap;
    EXPECT_NEAR(r.positions(i, 2), gap ? 0.0 : 0.5 * kHeight, 1e-15) << i;
  }
  EXPECT_EQ(r.limited, cells_count);
  EXPECT_EQ(r.lowered, 441u);
  for (const double d : {0.0, 0.5}) {
    LowerRaisedCellsParams off = params();
    off.max_depth = d;
    off.height = d == 0.0 ? kHeight : 0.0;
    const LowerRaisedCellsResult o =
        lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, off);
    EXPECT_EQ(o.limited, 0u) << d;
    for (int i = 0; i < 441; ++i) EXPECT_NEAR(o.positions(i, 2), 0.0, 1e-15) << i;
  }
}

// A point the update already carried down past its input (t > 0: its input
// lies above its output) sinks at most d h - t more; once t >= d h it stays.
TEST(LowerRaisedCells, APointAlreadyBelowItsInputSinksOnlyToTheLimit) {
  Cells c = cells();
  const int deep = 10 * 21 + 10, low = 10 * 21 + 11;  // two cells, not gaps
  c.updated(deep, 2) = -0.05;                         // t = h + 0.05 >= d h: stays
  c.updated(low, 2) = 0.2;                            // t = 0.1: sinks 0.2 more, to 0
  LowerRaisedCellsParams p = params();
  p.max_depth = 1.0;
  const LowerRaisedCellsResult r =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, p);
  EXPECT_EQ(r.positions(deep, 2), -0.05);
  EXPECT_NEAR(r.positions(low, 2), 0.0, 1e-15);
  p.max_depth = 0.0;  // without the limit, the mean of the feet around it
  const LowerRaisedCellsResult unlimited =
      lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, p);
  EXPECT_LT(unlimited.positions(deep, 2), -0.05 - 0.5 * kHeight);
}

// The turn test: a cell whose output normal points down (-z), against its
// neighbors' (+z), sinks along their mean, to the feet at z = 0, and counts
// as turned; along its own normal it would have risen to 2 h. One whose
// normal is 80° off (within max_turn_deg = 90) sinks along its own normal.
TEST(LowerRaisedCells, APointWhoseNormalTurnedOverSinksAlongItsNeighbors) {
  const Cells c = cells();
  const int against = 10 * 21 + 10, tilted = 4 * 21 + 4;  // two cells, not gaps, apart
  Normals N = c.N;
  N.row(against) << 0.0, 0.0, -1.0;
  const double a = 80.0 * M_PI / 180.0;
  N.row(tilted) << std::sin(a), 0.0, std::cos(a);
  const LowerRaisedCellsResult r =
      lower_raised_cells(c.P, c.updated, N, c.is_texture, -0.8, c.R, params());
  EXPECT_NEAR(r.positions(against, 2), 0.0, 1e-15);
  EXPECT_EQ(r.turned, 1u);
  EXPECT_EQ(r.lowered, 441u);
  const Eigen::RowVector3d along = c.updated.row(tilted) - kHeight * N.row(tilted);
  EXPECT_NEAR((r.positions.row(tilted) - along).norm(), 0.0, 1e-15);
  LowerRaisedCellsParams off = params();
  off.max_turn_deg = 180.0;
  const LowerRaisedCellsResult o =
      lower_raised_cells(c.P, c.updated, N, c.is_texture, -0.8, c.R, off);
  EXPECT_NEAR(o.positions(against, 2), 2.0 * kHeight, 1e-15);
  EXPECT_EQ(o.turned, 0u);
}

TEST(LowerRaisedCells, RejectsBadParametersAndSizes) {
  const Cells c = cells();
  auto run = [&](const LowerRaisedCellsParams& p) {
    return lower_raised_cells(c.P, c.updated, c.N, c.is_texture, -0.8, c.R, p);
  };
  LowerRaisedCellsParams p = params();
  p.low_quantile = -0.1;
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.spread_quantile = 1.5;
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.radius = 0.0;
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.min_lean = 0.0;
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.min_share = std::nan("");
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.max_depth = -1.0;
  EXPECT_THROW(run(p), std::invalid_argument);
  p = params();
  p.max_turn_deg = 0.0;
  EXPECT_THROW(run(p), std::invalid_argument);
  p.max_turn_deg = 181.0;
  EXPECT_THROW(run(p), std::invalid_argument);
  const Normals short_normals = Normals::Zero(10, 3);
  EXPECT_THROW(lower_raised_cells(c.P, c.updated, short_normals, c.is_texture, -0.8, c.R, params()),
               std::invalid_argument);
  p = params();
  p.height = std::nan("");
  EXPECT_THROW(run(p), std::invalid_argument);
  const std::vector<std::uint8_t> short_labels(10, 1);
  EXPECT_THROW(lower_raised_cells(c.P, c.updated, c.N, short_labels, -0.8, c.R, params()),
               std::invalid_argument);
}

// The whole method on a sphere of radius 0.5 covered edge to edge in scales
// 0.01 high (synth's dense scales, R = 0.03, r = 1.5 R): left on the cells'
// tops, the output lies farther out than the input on average (the gaps
// lifted to the tops); lowered, it lies within a fifth of the scales' height
// of the sphere, and its rms distance from it is under a third of the
// input's.
TEST(LowerRaisedCells, ScalesOnASphereEndOnTheSphere) {
  SynthParams sp;
  sp.shape = BaseShape::Sphere;
  sp.texture = TextureKind::Scales;
  sp.layout = TextureLayout::Dense;
  sp.size = 0.03;
  sp.amplitude = 0.01;
  sp.points = 20000;
  sp.ground_truth_points = 10;
  const SynthesizedShape s = synthesize_shape(sp);
  RemoveTextureParams p;
  p.radius = {0.045, Length::Unit::Absolute};
  auto off_sphere = [](const Positions& X) {
    return (X.rowwise().norm().array() - 0.5).matrix().eval();
  };
  const Eigen::VectorXd input = off_sphere(s.positions);
  const RemoveTextureResult lowered = remove_texture(s.positions, s.normals, p);
  p.raised_cells.enabled = false;
  const RemoveTextureResult tops = remove_texture(s.positions, s.normals, p);

  EXPECT_LT(lowered.report.relief_lean, -0.5);
  EXPECT_GT(lowered.report.raised_cells_lowered, 19000u);
  EXPECT_EQ(tops.report.raised_cells_lowered, 0u);
  EXPECT_GT(off_sphere(tops.positions).mean(), input.mean());
  EXPECT_LT(std::abs(off_sphere(lowered.positions).mean()), 0.2 * sp.amplitude);
  auto rms = [](const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); };
  EXPECT_LT(rms(off_sphere(lowered.positions)), rms(input) / 3.0);
}

}  // namespace
}  // namespace detexture
