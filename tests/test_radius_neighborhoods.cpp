#include "detexture/geometry/radius_neighborhoods.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace detexture {
namespace {

Positions random_cloud(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Positions P(n, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) P(i, d) = u(rng);
  return P;
}

TEST(RadiusNeighborhoods, AgreesWithBruteForce) {
  const Positions P = random_cloud(3000, 7);
  const double radius = 0.15;
  const Neighborhoods N = radius_neighborhoods(P, {radius, 0});
  ASSERT_EQ(N.size(), 3000u);
  for (int i = 0; i < P.rows(); ++i) {
    std::vector<std::uint32_t> expected;
    for (int j = 0; j < P.rows(); ++j)
      if ((P.row(i) - P.row(j)).squaredNorm() <= radius * radius) expected.push_back(j);
    std::vector<std::uint32_t> got(N.begin(i), N.end(i));
    EXPECT_EQ(got.front(), static_cast<std::uint32_t>(i)) << "self comes first";
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected) << "point " << i;
  }
}

TEST(RadiusNeighborhoods, SortedByDistanceAndCapKeepsNearest) {
  const Positions P = random_cloud(2000, 11);
  const Neighborhoods all = radius_neighborhoods(P, {0.3, 0});
  const Neighborhoods capped = radius_neighborhoods(P, {0.3, 8});
  for (int i = 0; i < P.rows(); ++i) {
    double last = -1.0;
    for (auto it = all.begin(i); it != all.end(i); ++it) {
      const double d = (P.row(i) - P.row(*it)).squaredNorm();
      EXPECT_GE(d, last);
      last = d;
    }
    const std::size_t expect = std::min<std::size_t>(8, all.count(i));
    ASSERT_EQ(capped.count(i), expect);
    EXPECT_TRUE(std::equal(capped.begin(i), capped.end(i), all.begin(i)));
  }
}

// Equal distances (a regular grid, and duplicated points) are ordered by
// index; distances bunched at the rim exercise the distance buckets.
TEST(RadiusNeighborhoods, TiesOrderedByIndex) {
  Positions P(0, 3);
  std::vector<Eigen::RowVector3d> rows;
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y) rows.emplace_back(x, y, 0.0);
  for (int k = 0; k < 5; ++k) rows.emplace_back(0.0, 0.0, 0.0);  // duplicates of the centre
  for (int k = 0; k < 40; ++k)  // a ring just inside the radius, and its twin
    rows.emplace_back(2.99 * std::cos(k * 0.157), 2.99 * std::sin(k * 0.157), 0.0);
  P.resize(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = rows[i];
  const Neighborhoods N = radius_neighborhoods(P, {3.0, 0});
  for (int i = 0; i < P.rows(); ++i) {
    std::vector<std::uint32_t> expected;
    for (int j = 0; j < P.rows(); ++j)
      if ((P.row(i) - P.row(j)).squaredNorm() < 9.0) expected.push_back(j);
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
      return static_cast<float>((P.row(i) - P.row(a)).squaredNorm()) <
             static_cast<float>((P.row(i) - P.row(b)).squaredNorm());
    });
    const std::vector<std::uint32_t> got(N.begin(i), N.end(i));
    ASSERT_EQ(got, expected) << "point " << i;
  }
}

// Cutting R at a smaller radius gives the neighborhoods of that radius.
TEST(RadiusNeighborhoods, ShrinkKeepsTheInnerPrefix) {
  const Positions P = random_cloud(4000, 5);
  Neighborhoods R = radius_neighborhoods(P, {0.2, 0});
  const Neighborhoods inner = radius_neighborhoods(P, {0.1, 0});
  shrink_neighborhoods(R, P, 0.1);
  EXPECT_EQ(R.offsets, inner.offsets);
  EXPECT_EQ(R.indices, inner.indices);
  EXPECT_TRUE(R.symmetric);
  EXPECT_THROW(shrink_neighborhoods(R, P, -1.0), std::invalid_argument);
  EXPECT_THROW(shrink_neighborhoods(R, random_cloud(10, 1), 0.1), std::invalid_argument);
}

TEST(RadiusNeighborhoods, IdenticalForAnyThreadCount) {
  const Positions P = random_cloud(20000, 3);
  omp_set_num_threads(1);
  const Neighborhoods a = radius_neighborhoods(P, {0.1, 0});
  omp_set_num_threads(2);
  const Neighborhoods b = radius_neighborhoods(P, {0.1, 0});
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.indices, b.indices);
}

TEST(RadiusNeighborhoods, IsolatedPointsCountedNotFatal) {
  Positions P(3, 3);
  P << 0, 0, 0, 10, 0, 0, 10.05, 0, 0;
  const Neighborhoods N = radius_neighborhoods(P, {0.1, 0});
  const NeighborhoodStats s = neighborhood_stats(N, 2);
  EXPECT_EQ(s.min, 1u);
  EXPECT_EQ(s.max, 2u);
  EXPECT_EQ(s.sparse_points, 1u);
}

TEST(RadiusNeighborhoods, RejectsBadRadius) {
  const Positions P = random_cloud(10, 1);
  EXPECT_THROW(radius_neighborhoods(P, {0.0, 0}), std::invalid_argument);
  EXPECT_THROW(radius_neighborhoods(P, {-1.0, 0}), std::invalid_argument);
  EXPECT_THROW(radius_neighborhoods(P, {std::nan(""), 0}), std::invalid_argument);
}

TEST(KnnNeighborhoods, AgreesWithBruteForce) {
  const Positions P = random_cloud(500, 5);
  const Neighborhoods N = knn_neighborhoods(P, 6);
  for (int i = 0; i < P.rows(); ++i) {
    std::vector<std::pair<double, int>> d;
    for (int j = 0; j < P.rows(); ++j) d.emplace_back((P.row(i) - P.row(j)).squaredNorm(), j);
    std::sort(d.begin(), d.end());
    ASSERT_EQ(N.count(i), 6u);
    for (int t = 0; t < 6; ++t) EXPECT_EQ(N.begin(i)[t], static_cast<std::uint32_t>(d[t].second));
  }
}

}  // namespace
}  // namespace detexture
