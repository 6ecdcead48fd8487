#include "detexture/geometry/point_index.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace detexture {
namespace {

TEST(PointIndex, AgreesWithBruteForceFromOtherPoints) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Positions P(2000, 3), Q(300, 3);
  for (int i = 0; i < P.rows(); ++i) P.row(i) << u(rng), u(rng), u(rng);
  for (int i = 0; i < Q.rows(); ++i) Q.row(i) << u(rng), u(rng), u(rng);
  const PointIndex index(P);
  std::vector<std::pair<std::uint32_t, double>> found;
  std::vector<std::uint32_t> knn;
  std::vector<double> knn_sq;
  for (int q = 0; q < Q.rows(); ++q) {
    const double x[3] = {Q(q, 0), Q(q, 1), Q(q, 2)};
    std::vector<std::pair<double, std::uint32_t>> all;
    for (int i = 0; i < P.rows(); ++i) all.emplace_back((P.row(i) - Q.row(q)).squaredNorm(), i);
    std::sort(all.begin(), all.end());
    double d = 0.0;
    EXPECT_EQ(index.nearest(x, &d), all[0].second);
    EXPECT_DOUBLE_EQ(d, all[0].first);
    index.nearest(x, 5, knn, knn_sq);
    ASSERT_EQ(knn.size(), 5u);
    for (int t = 0; t < 5; ++t) EXPECT_EQ(knn[t], all[t].second);
    index.within(x, 0.2, found);  // a radius, not its square
    std::size_t inside = 0;
    while (inside < all.size() && all[inside].first <= 0.04) ++inside;
    EXPECT_EQ(found.size(), inside);
  }
}

}  // namespace
}  // namespace detexture
