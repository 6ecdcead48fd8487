#include "detexture/pipeline/update_positions.h"

#include <gtest/gtest.h>

#include <cmath>

#include "detexture/pipeline/detect_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

// A plane with a bump of height 0.03, its neighborhoods (r = 0.06), texture
// labels and the filtered normals all +z: the update's input, worked out.
struct BumpCase {
  test::BumpyPlane s;
  Neighborhoods R;
  TextureDetection det;
  Normals up;
  UpdatePositionsParams params;
};

BumpCase bump_case(int side) {
  BumpCase c;
  c.s = test::bumpy_plane(side, 0.03, 0.03);
  c.R = radius_neighborhoods(c.s.P, {0.06, 0});
  DetectTextureParams tp;
  tp.lambda = 0.002;
  c.det = detect_texture(c.s.P, c.R, tp);
  c.up.resize(c.s.P.rows(), 3);
  c.up.rowwise() = Eigen::RowVector3d(0, 0, 1);
  c.params.sigma_p = 0.03;
  c.params.solve_radius = 0.03;
  return c;
}

// The filtered normals of a plane with a bump are all +z; the bump's points
// are texture (detect_texture). The global solve carries them down onto the
// plane; the paper's local update only averages heights and leaves part of
// the bump standing.
TEST(UpdatePositions, GlobalPutsBumpBackOnPlane) {
  auto [s, R, det, up, params] = bump_case(101);
  const UpdatePositionsResult global = update_positions(s.P, up, R, det.is_texture, params);
  params.mode = UpdateMode::Isotropic;
  const UpdatePositionsResult local = update_positions(s.P, up, R, det.is_texture, params);
  const double top = s.height.maxCoeff();
  EXPECT_LT(global.positions.col(2).cwiseAbs().maxCoeff(), 0.1 * top);
  EXPECT_GT(local.positions.col(2).cwiseAbs().maxCoeff(), 0.3 * top);
  // x and y do not change: points move along their normal only.
  EXPECT_LT((global.positions.leftCols(2) - s.P.leftCols(2)).cwiseAbs().maxCoeff(), 1e-12);
}

// A noisy plane whose points all count as surface (the noise is below λ):
// anchored fully, every point keeps most of its noise; with the anchors
// falling off with the height above the fitted surface, the noisy points
// settle closer to the plane. On a clean plane both are exact.
TEST(UpdatePositions, AnchorsFallOffWithTheHeightAboveTheFittedSurface) {
  auto [s, R, det, up, params] = bump_case(61);
  Positions noisy = s.P;
  noisy.col(2).setZero();
  std::vector<float> height(static_cast<std::size_t>(noisy.rows()));
  for (Eigen::Index i = 0; i < noisy.rows(); ++i) {
    // ±0.001 in a checkerboard: every point 0.001 off the plane z = 0.
    noisy(i, 2) = ((i + i / 61) % 2 == 0 ? 1.0 : -1.0) * 0.001;
    height[static_cast<std::size_t>(i)] = 0.001f;
  }
  const std::vector<std::uint8_t> surface(static_cast<std::size_t>(noisy.rows()), 0);
  const auto rms = [](const Positions& Q) {
    return std::sqrt(Q.col(2).squaredNorm() / static_cast<double>(Q.rows()));
  };
  const double held = rms(update_positions(noisy, up, R, surface, height, params).positions);
  params.anchor_height = 0.0005;  // the points sit 2 s off: weight e^-2 of the full anchor
  const double freed = rms(update_positions(noisy, up, R, surface, height, params).positions);
  EXPECT_GT(held, 0.3e-3);  // anchored fully: about half the noise stays
  EXPECT_LT(freed, 0.5 * held);
  // A clean plane (height 0 everywhere) does not move, whatever the scale.
  Positions flat = noisy;
  flat.col(2).setZero();
  const std::vector<float> zero(height.size(), 0.0f);
  EXPECT_LT(
      update_positions(flat, up, R, surface, zero, params).positions.col(2).cwiseAbs().maxCoeff(),
      1e-15);
  // The heights are required when the anchors fall off.
  EXPECT_THROW(update_positions(noisy, up, R, surface, {}, params), std::invalid_argument);
}

// The same noisy plane, every point at height 0 above its fitted surface (so
// the height fall-off holds all fully), with input normals tilted by 30°
// from the filtered +z, as on the foot of a bump. At an angle scale of 15°
// each surface anchor keeps exp(-2) of its weight and the points settle as
// when the height fall-off freed them; input normals that agree with the
// filtered ones, or zero ones (no evidence), leave the result unchanged.
TEST(UpdatePositions, AnchorsFallOffWithTheTiltOfTheInputNormal) {
  auto [s, R, det, up, params] = bump_case(61);
  Positions noisy = s.P;
  for (Eigen::Index i = 0; i < noisy.rows(); ++i)
    noisy(i, 2) = ((i + i / 61) % 2 == 0 ? 1.0 : -1.0) * 0.001;
  const std::vector<float> zero(static_cast<std::size_t>(noisy.rows()), 0.0f);
  const std::vector<std::uint8_t> surface(zero.size(), 0);
  const auto rms = [](const Positions& Q) {
    return std::sqrt(Q.col(2).squaredNorm() / static_cast<double>(Q.rows()));
  };
  const double t = 30.0 * M_PI / 180.0;
  Normals tilted(noisy.rows(), 3);
  tilted.rowwise() = Eigen::RowVector3d(std::sin(t), 0.0, std::cos(t));
  const Positions held = update_positions(noisy, up, R, surface, zero, tilted, params).positions;
  params.anchor_angle_deg = 15.0;
  const Positions freed = update_positions(noisy, up, R, surface, zero, tilted, params).positions;
  EXPECT_GT(rms(held), 0.3e-3);  // anchored fully: about half the noise stays
  EXPECT_LT(rms(freed), 0.5 * rms(held));
  EXPECT_EQ(update_positions(noisy, up, R, surface, zero, up, params).positions, held);
  const Normals none = Normals::Zero(noisy.rows(), 3);
  EXPECT_EQ(update_positions(noisy, up, R, surface, zero, none, params).positions, held);
  // Texture points are anchored weakly whatever their normals: unchanged.
  const std::vector<std::uint8_t> texture(zero.size(), 1);
  params.anchor_angle_deg = 0.0;
  const Positions weak = update_positions(noisy, up, R, texture, zero, tilted, params).positions;
  params.anchor_angle_deg = 15.0;
  EXPECT_EQ(update_positions(noisy, up, R, texture, zero, tilted, params).positions, weak);
  // The input normals are required when the anchors fall off with them.
  EXPECT_THROW(update_positions(noisy, up, R, surface, zero, params), std::invalid_argument);
  params.anchor_angle_deg = -1.0;
  EXPECT_THROW(update_positions(noisy, up, R, surface, zero, tilted, params),
               std::invalid_argument);
}

// Per-point anchor factors (remove_texture's second pass over waves left in
// the positions): the noisy plane, all surface, every anchor scaled by
// e^-2 settles closer to the plane, as when the height fall-off weighs
// each anchor by e^-2; factors of 1 change nothing; bad factors are refused.
TEST(UpdatePositions, AnchorScaleWeighsEachPointsAnchor) {
  auto [s, R, det, up, params] = bump_case(61);
  Positions noisy = s.P;
  for (Eigen::Index i = 0; i < noisy.rows(); ++i)
    noisy(i, 2) = ((i + i / 61) % 2 == 0 ? 1.0 : -1.0) * 0.001;
  const std::size_t n = static_cast<std::size_t>(noisy.rows());
  const std::vector<float> zero(n, 0.0f);
  const std::vector<std::uint8_t> surface(n, 0);
  const auto rms = [](const Positions& Q) {
    return std::sqrt(Q.col(2).squaredNorm() / static_cast<double>(Q.rows()));
  };
  const Positions held = update_positions(noisy, up, R, surface, zero, up, params).positions;
  const std::vector<float> ones(n, 1.0f);
  EXPECT_EQ(update_positions(noisy, up, R, surface, zero, up, ones, params).positions, held);
  const std::vector<float> low(n, static_cast<float>(std::exp(-2.0)));
  const Positions freed = update_positions(noisy, up, R, surface, zero, up, low, params).positions;
  EXPECT_GT(rms(held), 0.3e-3);
  EXPECT_LT(rms(freed), 0.5 * rms(held));
  // Lowered on the left half only: the right half stays as held.
  std::vector<float> half(n, 1.0f);
  for (std::size_t i = 0; i < n; ++i)
    if (noisy(static_cast<Eigen::Index>(i), 0) < 0.4) half[i] = 1e-4f;
  const Positions part = update_positions(noisy, up, R, surface, zero, up, half, params).positions;
  double left = 0.0, right = 0.0;
  int nl = 0, nr = 0;
  for (Eigen::Index i = 0; i < noisy.rows(); ++i) {
    if (noisy(i, 0) < 0.3) {
      left += std::abs(part(i, 2));
      ++nl;
    } else if (noisy(i, 0) > 0.6) {
      right += std::abs(part(i, 2) - held(i, 2));
      ++nr;
    }
  }
  EXPECT_LT(left / nl, 0.2e-3);
  EXPECT_LT(right / nr, 1e-6);
  EXPECT_THROW(
      update_positions(noisy, up, R, surface, zero, up, std::vector<float>(n - 1, 1.0f), params),
      std::invalid_argument);
  std::vector<float> bad = ones;
  bad[7] = -1.0f;
  EXPECT_THROW(update_positions(noisy, up, R, surface, zero, up, bad, params),
               std::invalid_argument);
}

// The move limit cuts every move longer than it to its length, along the
// same direction, and counts those points; shorter moves are untouched.
TEST(UpdatePositions, MoveLimitCutsLongMovesOnly) {
  auto [s, R, det, up, params] = bump_case(61);
  const UpdatePositionsResult free = update_positions(s.P, up, R, det.is_texture, params);
  params.max_move = 0.01;
  const UpdatePositionsResult cut = update_positions(s.P, up, R, det.is_texture, params);
  std::size_t long_moves = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double free_move = (free.positions.row(i) - s.P.row(i)).norm();
    const Eigen::RowVector3d step = cut.positions.row(i) - s.P.row(i);
    if (free_move > 0.01) {
      ++long_moves;
      EXPECT_NEAR(step.norm(), 0.01, 1e-12);
      EXPECT_NEAR(step.normalized().dot((free.positions.row(i) - s.P.row(i)) / free_move), 1.0,
                  1e-12);
    } else {
      EXPECT_EQ(cut.positions.row(i), free.positions.row(i));
    }
  }
  EXPECT_GT(long_moves, 10u);
  EXPECT_EQ(cut.limited, long_moves);
}

// On a sphere with its exact normals the global update leaves the points on
// the sphere: no shrinking, no expansion. The paper's point-by-point updates
// fit each point to its neighbors' tangent planes, which lie outside a convex
// surface, so they expand it by about the mean of w·d²/(2R) — the "external
// expansion" of the paper's Table 3.
TEST(UpdatePositions, SphereKeepsItsRadius) {
  const auto s = test::fibonacci_sphere(20000, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  const std::vector<std::uint8_t> none(s.P.rows(), 0);
  for (UpdateMode mode : {UpdateMode::Global, UpdateMode::Isotropic, UpdateMode::Eq9}) {
    UpdatePositionsParams params;
    params.mode = mode;
    params.sigma_p = 0.05;
    params.solve_radius = 0.05;
    const UpdatePositionsResult u = update_positions(s.P, s.N, R, none, params);
    const double mean_radius = u.positions.rowwise().norm().mean();
    if (mode == UpdateMode::Global)
      EXPECT_NEAR(mean_radius, 1.0, 1e-4);
    else
      EXPECT_GT(mean_radius, 1.0005) << "mode " << static_cast<int>(mode);
  }
}

TEST(UpdatePositions, IsolatedPointsStay) {
  Positions P(2, 3);
  P << 0, 0, 0, 5, 0, 0;
  Normals N(2, 3);
  N << 0, 0, 1, 0, 0, 1;
  const Neighborhoods R = radius_neighborhoods(P, {0.1, 0});
  UpdatePositionsParams params;
  params.sigma_p = 0.05;
  const UpdatePositionsResult u = update_positions(P, N, R, {0, 0}, params);
  EXPECT_EQ(u.isolated, 2u);
  EXPECT_EQ(u.positions, P);
}

TEST(UpdatePositions, RejectsBadParameters) {
  const auto s = test::bumpy_plane(5, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.5, 0});
  UpdatePositionsParams params;
  EXPECT_THROW(update_positions(s.P, s.N, R, {}, params), std::invalid_argument);
  params.sigma_p = 0.1;
  EXPECT_THROW(update_positions(s.P, s.N, R, {}, params), std::invalid_argument)
      << "global needs labels";
  params.isotropy_deg = 0.0;
  params.mode = UpdateMode::Isotropic;
  EXPECT_THROW(update_positions(s.P, s.N, R, {}, params), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
