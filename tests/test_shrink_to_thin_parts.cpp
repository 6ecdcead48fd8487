// shrink_to_thin_parts: on a limb thinner than r every neighborhood shrinks
// to the limb's scale (never below the floor); a single sheet, or a floor of
// 1, leaves R as it was; neighborhoods stay symmetric.
#include "detexture/geometry/shrink_to_thin_parts.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace detexture {
namespace {

struct Cloud {
  Positions P;
  Normals N;
};

// A closed tube of radius rho along z, `rings` rings of `around` points,
// outward normals.
Cloud tube(double rho, int around, int rings, double step) {
  Cloud c;
  c.P.resize(around * rings, 3);
  c.N.resize(around * rings, 3);
  for (int k = 0; k < rings; ++k)
    for (int a = 0; a < around; ++a) {
      const double t = 2.0 * M_PI * a / around;
      c.P.row(k * around + a) << rho * std::cos(t), rho * std::sin(t), k * step;
      c.N.row(k * around + a) << std::cos(t), std::sin(t), 0.0;
    }
  return c;
}

double farthest(const Neighborhoods& R, const Positions& P, std::size_t i) {
  double d = 0.0;
  for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j)
    d = std::max(d, (P.row(*j) - P.row(i)).norm());
  return d;
}

bool symmetric(const Neighborhoods& R) {
  for (std::size_t i = 0; i < R.size(); ++i)
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j)
      if (std::find(R.begin(*j), R.end(*j), static_cast<std::uint32_t>(i)) == R.end(*j))
        return false;
  return true;
}

TEST(ShrinkToThinParts, NeighborhoodsOnALimbShrinkToTheFloor) {
  // Radius 0.01, r = 0.05: the nearest back (normals > 120° apart) is at a
  // chord of at least 2 ρ sin 60° = 0.0173, below the floor 0.5 r = 0.025.
  const Cloud c = tube(0.01, 24, 80, 0.0025);
  Neighborhoods R = radius_neighborhoods(c.P, {0.05, 0});
  std::size_t before = 0;
  for (std::size_t i = 0; i < R.size(); ++i) before = std::max(before, R.count(i));
  ASSERT_GT(farthest(R, c.P, 1000), 0.045);
  const ShrinkToThinPartsResult out = shrink_to_thin_parts(R, c.P, c.N, {0.05, 0.5, 120.0});
  EXPECT_EQ(out.points, R.size());
  EXPECT_GT(out.removed, 0u);
  for (std::size_t i = 0; i < R.size(); ++i) {
    EXPECT_LE(farthest(R, c.P, i), 0.025 + 1e-12) << i;
    EXPECT_EQ(R.begin(i)[0], i) << "the point itself stays first";
  }
  EXPECT_TRUE(symmetric(R));
  // A floor below the back's distance: r_i is the distance of the back, here
  // the point 135° around the same ring (the first past 125°; steps of 15°).
  R = radius_neighborhoods(c.P, {0.05, 0});
  shrink_to_thin_parts(R, c.P, c.N, {0.05, 0.1, 125.0});
  const double chord_135 = 2.0 * 0.01 * std::sin(M_PI * 135.0 / 360.0);
  EXPECT_NEAR(farthest(R, c.P, 1000), chord_135, 1e-9);
  EXPECT_TRUE(symmetric(R));
}

TEST(ShrinkToThinParts, ASingleSheetOrAFloorOfOneKeepsEveryNeighbor) {
  // A sphere of radius 0.5 with r = 0.1: curved, but no back within r.
  Cloud sphere;
  const int m = 3000;
  sphere.P.resize(m, 3);
  sphere.N.resize(m, 3);
  for (int i = 0; i < m; ++i) {  // Fibonacci sphere
    const double z = 1.0 - 2.0 * (i + 0.5) / m, rho = std::sqrt(1.0 - z * z);
    const double t = M_PI * (3.0 - std::sqrt(5.0)) * i;
    sphere.N.row(i) << rho * std::cos(t), rho * std::sin(t), z;
    sphere.P.row(i) = 0.5 * sphere.N.row(i);
  }
  Neighborhoods R = radius_neighborhoods(sphere.P, {0.1, 0});
  const Neighborhoods before = R;
  const ShrinkToThinPartsResult out =
      shrink_to_thin_parts(R, sphere.P, sphere.N, {0.1, 0.5, 120.0});
  EXPECT_EQ(out.points, 0u);
  EXPECT_EQ(R.indices, before.indices);
  const Cloud c = tube(0.01, 24, 40, 0.0025);
  R = radius_neighborhoods(c.P, {0.05, 0});
  const Neighborhoods whole = R;
  EXPECT_EQ(shrink_to_thin_parts(R, c.P, c.N, {0.05, 1.0, 120.0}).points, 0u);
  EXPECT_EQ(R.indices, whole.indices);
  EXPECT_EQ(R.offsets, whole.offsets);
}

TEST(ShrinkToThinParts, APlateKeepsItsNeighborhoods) {
  // Two sheets 0.02 apart facing away (a plate or a wall), r = 0.05: the
  // back is straight through, so nothing shrinks (drop_opposite_neighbors
  // separates the sheets); with no plate test (angle 0) every row would.
  Cloud plate;
  const int side = 30;
  plate.P.resize(2 * side * side, 3);
  plate.N.resize(2 * side * side, 3);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const int i = a * side + b;
      plate.P.row(i) << a * 0.005, b * 0.005, 0.0;
      plate.N.row(i) << 0.0, 0.0, 1.0;
      plate.P.row(side * side + i) << a * 0.005, b * 0.005, -0.02;
      plate.N.row(side * side + i) << 0.0, 0.0, -1.0;
    }
  Neighborhoods R = radius_neighborhoods(plate.P, {0.05, 0});
  const Neighborhoods before = R;
  EXPECT_EQ(shrink_to_thin_parts(R, plate.P, plate.N, {0.05, 0.5, 120.0, 15.0}).points, 0u);
  EXPECT_EQ(R.indices, before.indices);
  EXPECT_EQ(shrink_to_thin_parts(R, plate.P, plate.N, {0.05, 0.5, 120.0, 0.0}).points, R.size());
}

TEST(ShrinkToThinParts, RefusesParametersOutOfRange) {
  const Cloud c = tube(0.01, 12, 4, 0.01);
  Neighborhoods R = radius_neighborhoods(c.P, {0.05, 0});
  EXPECT_THROW(shrink_to_thin_parts(R, c.P, c.N, {0.05, 0.0, 120.0}), std::invalid_argument);
  EXPECT_THROW(shrink_to_thin_parts(R, c.P, c.N, {0.05, 0.5, 90.0}), std::invalid_argument);
  EXPECT_THROW(shrink_to_thin_parts(R, c.P, c.N, {0.05, 0.5, 120.0, 90.0}), std::invalid_argument);
  EXPECT_THROW(shrink_to_thin_parts(R, c.P, c.N, {0.0, 0.5, 120.0}), std::invalid_argument);
  EXPECT_THROW(shrink_to_thin_parts(R, c.P, Normals(), {0.05, 0.5, 120.0}), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
