#include "detexture/geometry/spatial_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

Positions random_cloud(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Positions P(n, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) P(i, d) = u(rng);
  return P;
}

TEST(SpatialOrder, IsAPermutationThatGroupsOctants) {
  Positions P = random_cloud(5000, 3);
  P.row(0) << 0.0, 0.0, 0.0;  // the bounding box is the unit cube
  P.row(1) << 1.0, 1.0, 1.0;
  const std::vector<std::uint32_t> order = spatial_order(P);
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k);
  // Along a Morton curve each octant of the bounding box is one run.
  auto octant = [&](std::uint32_t i) {
    return (P(i, 0) >= 0.5 ? 1 : 0) | (P(i, 1) >= 0.5 ? 2 : 0) | (P(i, 2) >= 0.5 ? 4 : 0);
  };
  int changes = 0;
  for (std::size_t k = 1; k < order.size(); ++k)
    changes += octant(order[k]) != octant(order[k - 1]);
  EXPECT_EQ(changes, 7);
}

TEST(SpatialOrder, PermuteAndUnpermuteAreInverse) {
  const Positions P = random_cloud(100, 1);
  const auto order = spatial_order(P);
  const Matrix3 Q = permute_rows(P, order);
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(Q.row(k), P.row(order[k]));
  EXPECT_EQ(unpermute_rows(Q, order), P);
}

// remove_texture works in spatial order and answers in the caller's: the
// result does not depend on how the input happens to be ordered.
TEST(SpatialOrder, RemoveTextureDoesNotDependOnInputOrder) {
  const auto s = test::bumpy_plane(41, 0.03, 0.05);
  std::vector<int> shuffle(s.P.rows());
  std::iota(shuffle.begin(), shuffle.end(), 0);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(5));
  Positions P2(s.P.rows(), 3);
  Normals N2(s.P.rows(), 3);
  for (int k = 0; k < s.P.rows(); ++k) {
    P2.row(k) = s.P.row(shuffle[k]);
    N2.row(k) = s.N.row(shuffle[k]);
  }
  RemoveTextureParams params;
  params.radius = parse_length("0.2");
  const RemoveTextureResult a = remove_texture(s.P, s.N, params);
  const RemoveTextureResult b = remove_texture(P2, N2, params);
  for (int k = 0; k < s.P.rows(); ++k) {
    ASSERT_EQ(b.positions.row(k), a.positions.row(shuffle[k]));
    ASSERT_EQ(b.normals.row(k), a.normals.row(shuffle[k]));
    ASSERT_EQ(b.is_texture[k], a.is_texture[shuffle[k]]);
  }
}

}  // namespace
}  // namespace detexture
