// remove_texture on clouds that used to hang or answer wrongly (issue 11):
// exact duplicates, extreme coordinates, unusable input normals, and
// neighborhoods too large for the memory.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

// These clouds are hostile on purpose: radii that hold the whole cloud are
// what the memory guard and the duplicate merging are tested on, so the
// large-radius refusal (a parameter check that comes first) is switched off.
RemoveTextureParams absolute(double radius) {
  RemoveTextureParams p;
  p.radius = {radius, Length::Unit::Absolute};
  p.allow_large_radius = true;
  return p;
}

void expect_same_result(const RemoveTextureResult& a, const RemoveTextureResult& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.is_texture, b.is_texture);
  EXPECT_EQ(a.texture_height, b.texture_height);
}

// 5000 copies of one point and one other point took 19 s (cubic); now the
// copies are merged. Both distinct positions have a single neighbor: too few
// for a plane, so both keep their input position.
TEST(RemoveTextureHostile, ExactDuplicatesCostLinearTime) {
  Positions P(5001, 3);
  for (int i = 0; i < 5000; ++i) P.row(i) << 0.25, 0.5, 0.75;
  P.row(5000) << 1.25, 0.5, 0.75;
  const auto t0 = std::chrono::steady_clock::now();
  const RemoveTextureResult r = remove_texture(P, Normals(), absolute(2.0));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_EQ(r.report.duplicates_merged, 4999u);
  EXPECT_EQ(r.positions, P);
  EXPECT_EQ(r.input_positions, P);
  EXPECT_TRUE(r.positions.allFinite());
  EXPECT_TRUE(r.texture_height.isZero());
}

// Every point of a bumpy plane given twice: each copy gets exactly the result
// of the plane given once.
TEST(RemoveTextureHostile, DuplicatedCloudGivesTheResultOfTheDistinctOne) {
  const auto s = test::bumpy_plane(31, 0.03, 0.05);
  const auto n = s.P.rows();
  Positions P2(2 * n, 3);
  Normals N2(2 * n, 3);
  P2 << s.P, s.P.colwise().reverse();
  N2 << s.N, s.N.colwise().reverse();
  const RemoveTextureResult once = remove_texture(s.P, s.N, absolute(0.2));
  const RemoveTextureResult twice = remove_texture(P2, N2, absolute(0.2));
  EXPECT_EQ(twice.report.duplicates_merged, std::size_t(n));
  EXPECT_EQ(once.report.duplicates_merged, 0u);
  ASSERT_EQ(twice.positions.rows(), 2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    EXPECT_EQ(twice.positions.row(i), once.positions.row(i));
    EXPECT_EQ(twice.positions.row(2 * n - 1 - i), once.positions.row(i));
    EXPECT_EQ(twice.normals.row(2 * n - 1 - i), once.normals.row(i));
    EXPECT_EQ(twice.is_texture[2 * n - 1 - i], once.is_texture[i]);
  }
  EXPECT_EQ(twice.report.texture_points, 2 * once.report.texture_points);
}

TEST(RemoveTextureHostile, DiagonalOfExtremeExtentsNeitherOverflowsNorUnderflows) {
  Positions P(2, 3);
  P << 0, 0, 0, 3e300, -4e300, 0;
  EXPECT_DOUBLE_EQ(bounding_box_diagonal(P), 5e300);
  P << 0, 0, 0, 3e-300, 4e-300, 0;
  EXPECT_DOUBLE_EQ(bounding_box_diagonal(P), 5e-300);
  P << 1, 2, 3, 4, 6, 3;
  EXPECT_EQ(bounding_box_diagonal(P), 5.0);
}

// ±1e300 gave "radius must be positive, got inf" and ±1e-300 "all points
// coincide". Scaled by 2^1000 or 2^-900 (exact), the result is the unscaled one times
// the same power of two, to the last bit.
TEST(RemoveTextureHostile, ExtremeScalesGiveTheScaledResult) {
  const auto s = test::bumpy_plane(31, 0.03, 0.05);
  RemoveTextureParams p;
  p.radius = {0.1, Length::Unit::Diagonal};
  const RemoveTextureResult unit = remove_texture(s.P, s.N, p);
  for (const int e : {1000, -900}) {
    const double f = std::ldexp(1.0, e);
    const RemoveTextureResult r = remove_texture(s.P * f, s.N, p);
    EXPECT_EQ(r.positions, unit.positions * f) << "2^" << e;
    EXPECT_EQ(r.normals, unit.normals) << "2^" << e;
    EXPECT_EQ(r.is_texture, unit.is_texture) << "2^" << e;
    EXPECT_EQ(r.texture_height, unit.texture_height * f) << "2^" << e;
    EXPECT_EQ(r.report.radius, unit.report.radius * f);
    EXPECT_EQ(r.input_positions, s.P * f);
  }
  // Not a power of two: the same answer to rounding. Rounding can flip a
  // vote of Eq. 2 whose distance sits at λ; with the soft Ω (the default)
  // that shifts the neighbor's weight by one vote share, and the points near
  // it by ~1e-5 of the unit cloud (the bumps are 0.03 high). The hard labels
  // rarely change, but the global update's anchors follow each point's
  // height above its nearest RANSAC model (anchor_height), and rounding can
  // change which model that is: 2.7e-5 measured, within the soft Ω's bound.
  const RemoveTextureResult big = remove_texture(s.P * 1e300, s.N, p);
  EXPECT_LT(((big.positions / 1e300) - unit.positions).cwiseAbs().maxCoeff(), 5e-5);
  const RemoveTextureResult tiny = remove_texture(s.P * 1e-300, s.N, p);
  EXPECT_LT(((tiny.positions / 1e-300) - unit.positions).cwiseAbs().maxCoeff(), 5e-5);
  p.texture.subneighborhood = SubneighborhoodMode::Hard;
  const RemoveTextureResult unit_hard = remove_texture(s.P, s.N, p);
  const RemoveTextureResult big_hard = remove_texture(s.P * 1e300, s.N, p);
  EXPECT_LT(((big_hard.positions / 1e300) - unit_hard.positions).cwiseAbs().maxCoeff(), 5e-5);
  p.anchor_height = 0.0;  // anchors by label alone: the hard labels' answer to 1e-6
  const RemoveTextureResult unit_held = remove_texture(s.P, s.N, p);
  const RemoveTextureResult big_held = remove_texture(s.P * 1e300, s.N, p);
  EXPECT_LT(((big_held.positions / 1e300) - unit_held.positions).cwiseAbs().maxCoeff(), 1e-6);
}

// All-zero input normals (the reader zeroes NaN ones) were kept zero; now
// they are estimated from the positions, exactly as when there are none.
TEST(RemoveTextureHostile, AllZeroNormalsAreEstimatedAsWhenThereAreNone) {
  const auto s = test::bumpy_plane(31, 0.03, 0.05);
  const RemoveTextureResult none = remove_texture(s.P, Normals(), absolute(0.2));
  const RemoveTextureResult zero = remove_texture(s.P, Normals::Zero(s.P.rows(), 3), absolute(0.2));
  expect_same_result(zero, none);
  EXPECT_EQ(zero.report.normals_reestimated, std::size_t(s.P.rows()));
  EXPECT_GT(zero.input_normals.rowwise().norm().minCoeff(), 0.99) << "no zero normal left";
}

// The memory guard counts the neighbors of sampled points. On a regular grid
// the count is known: a radius of 1.5 spacings holds the point and its 8
// grid neighbors (9), everywhere but at the border.
TEST(RemoveTextureHostile, MemoryEstimateCountsSampledNeighbors) {
  const auto s = test::bumpy_plane(101, 0.0, 0.05);  // flat: spacing 0.01
  const NeighborhoodsMemoryEstimate e = estimate_neighborhoods_memory(s.P, {0.015, 0}, 256);
  EXPECT_EQ(e.sampled, 256u);
  EXPECT_GT(e.mean_neighbors, 8.7);
  EXPECT_LE(e.mean_neighbors, 9.0);
  EXPECT_EQ(e.max_neighbors, 9u);
  EXPECT_NEAR(e.bytes, 10201 * (4.2 * e.mean_neighbors + kBytesPerPoint), 1.0);
  const NeighborhoodsMemoryEstimate capped = estimate_neighborhoods_memory(s.P, {0.015, 5}, 256);
  EXPECT_EQ(capped.mean_neighbors, 5.0);
  // A radius covering everything: every sample sees all 10201 points.
  EXPECT_EQ(estimate_neighborhoods_memory(s.P, {2.0, 0}, 64).mean_neighbors, 10201.0);
  // Sure to exceed 10 MB after the second sample: (2·10201 + 62)/64 = 319.8
  // neighbors per point at least, 10201·(4.2·319.8 + 256) = 16.3 MB.
  const NeighborhoodsMemoryEstimate early = estimate_neighborhoods_memory(s.P, {2.0, 0}, 64, 1e7);
  EXPECT_EQ(early.sampled, 2u);
  EXPECT_NEAR(early.bytes, 10201 * (4.2 * (2 * 10201 + 62) / 64.0 + kBytesPerPoint), 1.0);
}

TEST(RemoveTextureHostile, MemoryGuardRefusesWithWhatToChange) {
  const auto s = test::bumpy_plane(101, 0.03, 0.05);
  RemoveTextureParams p = absolute(2.0);  // 10201 neighbors each: 437 MB
  p.memory_limit = 100u << 20;
  try {
    remove_texture(s.P, s.N, p);
    FAIL() << "no ResourceLimitError";
  } catch (const ResourceLimitError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("10201 neighbors per point"), std::string::npos) << m;
    EXPECT_NE(m.find("100.0 MiB"), std::string::npos) << m;
    EXPECT_NE(m.find("--radius"), std::string::npos) << m;
    EXPECT_NE(m.find("--max-neighbors"), std::string::npos) << m;
  }
  p.radius = {0.03, Length::Unit::Absolute};  // about 29 neighbors: 3.8 MB
  EXPECT_NO_THROW(remove_texture(s.P, s.N, p));
}

TEST(RemoveTextureHostile, MemorySizesParse) {
  EXPECT_EQ(parse_memory_size("4G"), 4ull << 30);
  EXPECT_EQ(parse_memory_size("500m"), 500ull << 20);
  EXPECT_EQ(parse_memory_size("1.5GB"), 3ull << 29);
  EXPECT_EQ(parse_memory_size("123456"), 123456u);
  EXPECT_EQ(parse_memory_size("none"), std::numeric_limits<std::uint64_t>::max());
  for (const char* bad : {"", "G", "-1G", "4X", "abc", "0"})
    EXPECT_THROW(parse_memory_size(bad), std::invalid_argument) << bad;
}

}  // namespace
}  // namespace detexture
