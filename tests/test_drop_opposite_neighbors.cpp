#include "detexture/geometry/drop_opposite_neighbors.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test_support.h"

namespace detexture {
namespace {

// Two sheets 0.02 apart facing away from each other (a thin plate): within
// r = 0.05 every point sees both, and only its own sheet must stay (normals
// 180° apart, each sheet behind the other).
struct Plate {
  Positions P;
  Normals N;
};

Plate thin_plate(int side, double thickness) {
  const auto s = test::bumpy_plane(side, 0.0, 1.0);
  Plate p;
  const Eigen::Index n = s.P.rows();
  p.P.resize(2 * n, 3);
  p.N.resize(2 * n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    p.P.row(i) = s.P.row(i);
    p.N.row(i) << 0, 0, 1;
    p.P.row(n + i) << s.P(i, 0), s.P(i, 1), -thickness;
    p.N.row(n + i) << 0, 0, -1;
  }
  return p;
}

TEST(DropOppositeNeighbors, KeepsOnlyTheOwnSheetOfAThinPlate) {
  const Plate p = thin_plate(41, 0.02);
  Neighborhoods R = radius_neighborhoods(p.P, {0.05, 0});
  std::size_t across = 0;
  for (std::size_t i = 0; i < R.size(); ++i)
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j)
      across += (p.P(i, 2) == 0.0) != (p.P(*j, 2) == 0.0);
  ASSERT_GT(across, 0u) << "the radius must reach the other sheet for the test to mean anything";
  const Neighborhoods before = R;
  const std::size_t removed = drop_opposite_neighbors(R, p.P, p.N, {});
  EXPECT_EQ(removed, across);
  for (std::size_t i = 0; i < R.size(); ++i) {
    std::vector<std::uint32_t> expected;
    for (const std::uint32_t* j = before.begin(i); j != before.end(i); ++j)
      if ((p.P(i, 2) == 0.0) == (p.P(*j, 2) == 0.0)) expected.push_back(*j);
    EXPECT_EQ(std::vector<std::uint32_t>(R.begin(i), R.end(i)), expected) << "row " << i;
  }
  EXPECT_TRUE(R.symmetric);
}

// A 90° fold rising from the flat half is a concave crease: its faces look
// at each other and stay at any angle unless any pair past the angle goes.
// With its normals turned round it is a convex ridge seen from the other
// side, back to back: split at 60°, kept at 120°.
TEST(DropOppositeNeighbors, SplitsConvexCreasesOnly) {
  auto s = test::folded_plane(31, 90.0);
  Neighborhoods concave = radius_neighborhoods(s.P, {0.1, 0});
  Neighborhoods any_pair = concave;
  EXPECT_EQ(drop_opposite_neighbors(concave, s.P, s.N, {}), 0u);
  EXPECT_GT(drop_opposite_neighbors(any_pair, s.P, s.N, {60.0, false}), 0u);
  s.N *= -1.0;
  Neighborhoods convex = radius_neighborhoods(s.P, {0.1, 0});
  Neighborhoods wide = convex;
  const std::size_t removed = drop_opposite_neighbors(convex, s.P, s.N, {});
  EXPECT_EQ(drop_opposite_neighbors(wide, s.P, s.N, {120.0}), 0u);
  // Exactly the pairs with one point on each face (off the crease line).
  std::size_t across = 0;
  const Neighborhoods all = radius_neighborhoods(s.P, {0.1, 0});
  for (std::size_t i = 0; i < all.size(); ++i)
    for (const std::uint32_t* j = all.begin(i); j != all.end(i); ++j)
      across += s.N.row(i).dot(s.N.row(*j)) < 0.5 &&
                (s.P.row(*j) - s.P.row(i)).dot(s.N.row(i)) < 0.0 &&
                (s.P.row(*j) - s.P.row(i)).dot(s.N.row(*j)) > 0.0;
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(removed, across);
}

TEST(DropOppositeNeighbors, ZeroNormalsAndStraightAngleKeepEverything) {
  Plate p = thin_plate(21, 0.02);
  Neighborhoods R = radius_neighborhoods(p.P, {0.08, 0});
  const Neighborhoods before = R;
  EXPECT_EQ(drop_opposite_neighbors(R, p.P, p.N, {180.0}), 0u);
  EXPECT_EQ(R.indices, before.indices);
  p.N.setZero();
  EXPECT_EQ(drop_opposite_neighbors(R, p.P, p.N, {}), 0u);
  EXPECT_EQ(R.indices, before.indices);
}

TEST(DropOppositeNeighbors, RejectsBadAngleAndSizes) {
  const Plate p = thin_plate(5, 0.02);
  Neighborhoods R = radius_neighborhoods(p.P, {0.5, 0});
  EXPECT_THROW(drop_opposite_neighbors(R, p.P, p.N, {0.0}), std::invalid_argument);
  EXPECT_THROW(drop_opposite_neighbors(R, p.P, p.N, {181.0}), std::invalid_argument);
  EXPECT_THROW(drop_opposite_neighbors(R, p.P, Normals(3, 3), {}), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
