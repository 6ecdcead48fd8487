#include "detexture/pipeline/keep_input_normals.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "detexture/eval/compare_to_ground_truth.h"
#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

KeepInputNormalsParams params_at(double radius, double lambda) {
  KeepInputNormalsParams p;
  p.radius = radius;
  p.lambda = lambda;
  return p;
}

// A plane whose points do not move, except one that moves by 1 (a bump
// taken down); the output normals so far are tilted by 10°. Points farther
// than ρ from the moved one take their input normal, exactly; the moved
// point and those within ρ of it keep the output normal, and so do texture
// points and points without an input normal.
TEST(KeepInputNormals, NormalsAreKeptWhereNothingNearMoved) {
  const auto s = test::bumpy_plane(21, 0.0, 1.0);  // a flat grid, spacing 0.05
  const Neighborhoods R = radius_neighborhoods(s.P, {0.12, 0});
  Positions updated = s.P;
  const int moved = 10 * 21 + 10;  // the centre
  updated(moved, 2) += 1.0;
  Normals output = s.N;
  const double t = 10.0 * M_PI / 180.0;
  output.col(1).setConstant(std::sin(t));
  output.col(2).setConstant(std::cos(t));
  std::vector<std::uint8_t> texture(s.P.rows(), 0);
  texture[0] = 1;
  Normals given = s.N;
  given.row(1).setZero();
  const KeepInputNormalsResult r =
      keep_input_normals(s.P, updated, given, output, texture, R, params_at(0.11, 0.01));
  std::size_t kept = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const bool near = (s.P.row(i) - s.P.row(moved)).norm() <= 0.11;
    if (near || i == 0 || i == 1) {
      EXPECT_TRUE(r.normals.row(i) == output.row(i)) << i;
    } else {
      EXPECT_LT(test::angle_deg(r.normals.row(i), s.N.row(i)), 1e-5) << i;
      ++kept;
    }
  }
  EXPECT_EQ(r.kept, kept);
  EXPECT_GT(kept, 300u);
  // Input normals signed the other way are taken signed like the output.
  const Normals flipped = -given;
  EXPECT_TRUE(keep_input_normals(s.P, updated, flipped, output, texture, R, params_at(0.11, 0.01))
                  .normals.isApprox(r.normals, 1e-12));
}

// The ramp: every point moves by the same distance d. Under low λ the input
// normal is taken, from high λ the output normal stays, halfway between the
// two the output is their normalized mean. high = 0 changes nothing.
TEST(KeepInputNormals, TheRampFollowsTheMove) {
  const auto s = test::bumpy_plane(11, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.2, 0});
  Normals output(s.P.rows(), 3);
  output.rowwise() = Eigen::RowVector3d(1.0, 0.0, 0.0);
  const KeepInputNormalsParams p = params_at(0.15, 1.0);
  ASSERT_EQ(p.low, 0.05);
  ASSERT_EQ(p.high, 0.2);
  const auto run = [&](double d, const KeepInputNormalsParams& q) {
    Positions updated = s.P;
    updated.col(0).array() += d;
    return keep_input_normals(s.P, updated, s.N, output, {}, R, q);
  };
  const Eigen::RowVector3d mean = Eigen::RowVector3d(1.0, 0.0, 1.0).normalized();
  for (int i = 0; i < s.P.rows(); ++i) {
    EXPECT_LT(test::angle_deg(run(0.04, p).normals.row(i), s.N.row(i)), 1e-5);
    EXPECT_TRUE(run(0.2, p).normals.row(i) == output.row(i));
    EXPECT_LT(test::angle_deg(run(0.125, p).normals.row(i), mean), 1e-5);
  }
  EXPECT_EQ(run(0.125, p).kept, static_cast<std::size_t>(s.P.rows()));
  EXPECT_EQ(run(0.2, p).kept, 0u);
  KeepInputNormalsParams off = p;
  off.high = 0.0;
  EXPECT_TRUE(run(0.0, off).normals == output);
}

TEST(KeepInputNormals, BadInputIsRefused) {
  const auto s = test::bumpy_plane(5, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.3, 0});
  KeepInputNormalsParams p = params_at(0.2, 0.01);
  EXPECT_NO_THROW(keep_input_normals(s.P, s.P, s.N, s.N, {}, R, p));
  p.low = 0.3;
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N, s.N, {}, R, p), std::invalid_argument);
  p.low = -0.1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.high = -1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.high = std::nan("");
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.0);
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.0, 0.01);
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N.topRows(3), s.N, {}, R, p), std::invalid_argument);
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N, s.N, std::vector<std::uint8_t>(2, 0), R, p),
               std::invalid_argument);
}

// Through remove_texture: synth's cube with bumps keeps the input normals
// away from its bumps, which changes the output normals only, brings them
// closer to the true ones, and keep_input high 0 restores the output
// before (the fit and its blend alone).
TEST(KeepInputNormals, RemoveTextureKeepsThemWhereTheSurfaceStayed) {
  SynthParams cp;
  cp.points = 6000;
  cp.ground_truth_points = 20000;
  const SynthesizedShape cube = synthesize_shape(cp);
  RemoveTextureParams p;
  p.threads = 2;
  const RemoveTextureResult kept = remove_texture(cube.positions, cube.normals, p);
  p.keep_input.high = 0.0;
  const RemoveTextureResult fitted = remove_texture(cube.positions, cube.normals, p);
  EXPECT_TRUE(kept.positions == fitted.positions);
  EXPECT_FALSE(kept.normals == fitted.normals);
  EXPECT_GT(kept.report.input_normals_kept, 0u);
  EXPECT_EQ(fitted.report.input_normals_kept, 0u);
  const auto error = [&](const RemoveTextureResult& r) {
    return compare_to_ground_truth(r.positions, r.normals, cube.ground_truth_positions,
                                   cube.ground_truth_normals)
        .mean_angle_degrees;
  };
  EXPECT_LT(error(kept), error(fitted));
}

}  // namespace
}  // namespace detexture
