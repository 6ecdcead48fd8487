// limit_neighborhoods_to_mesh: two sheets side by side (two fingers, a leg
// touching the body) are close in space but not along the mesh, so each
// R_i keeps its own sheet only, and the whole of it; a tighter path limit
// cuts the neighbors whose edge path is longer than the limit; a limit of 0
// leaves R as it was; neighborhoods stay symmetric.
#include "detexture/geometry/limit_neighborhoods_to_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

namespace detexture {
namespace {

// Two flat m × m grids of spacing h, the second `gap` above the first (same
// normals: no normal test tells them apart), each triangulated along the
// diagonals x = y: the shortest edge path between grid points (0,0) and
// (a,b) is h·(√2·min(|a|,|b|) + ||a|-|b||) when a and b have the same sign
// (within 1.09 × their distance), h·(|a|+|b|) otherwise (within √2 ×).
struct Sheets {
  Positions P;
  TriangleIndices T;
  int m = 0;
};

Sheets two_sheets(int m, double h, double gap) {
  Sheets s;
  s.m = m;
  s.P.resize(2 * m * m, 3);
  s.T.resize(2 * 2 * (m - 1) * (m - 1), 3);
  int t = 0;
  for (int k = 0; k < 2; ++k) {
    const int base = k * m * m;
    for (int y = 0; y < m; ++y)
      for (int x = 0; x < m; ++x) s.P.row(base + y * m + x) << x * h, y * h, k * gap;
    for (int y = 0; y + 1 < m; ++y)
      for (int x = 0; x + 1 < m; ++x) {
        const int a = base + y * m + x, b = a + 1, c = a + m, d = a + m + 1;
        s.T.row(t++) << a, b, d;
        s.T.row(t++) << a, d, c;
      }
  }
  return s;
}

std::set<std::uint32_t> row(const Neighborhoods& R, std::size_t i) {
  return {R.begin(i), R.end(i)};
}

TEST(LimitNeighborhoodsToMesh, EachSheetKeepsItselfWhole) {
  const double h = 0.1, r = 0.45;
  const Sheets s = two_sheets(12, h, 0.2);
  Neighborhoods R = radius_neighborhoods(s.P, {r, 0});
  const Neighborhoods before = R;
  LimitNeighborhoodsToMeshParams p;
  p.radius = r;
  p.path_factor = 1.5;
  const LimitNeighborhoodsToMeshResult out = limit_neighborhoods_to_mesh(R, s.P, s.T, p);
  const std::size_t half = static_cast<std::size_t>(s.m * s.m);
  std::size_t removed = 0;
  for (std::size_t i = 0; i < R.size(); ++i) {
    std::set<std::uint32_t> own;
    for (const std::uint32_t j : row(before, i))
      if ((j < half) == (i < half)) own.insert(j);
    // On a grid a path within the ball is at most √2 × the distance ≤ 1.42 r.
    EXPECT_EQ(row(R, i), own) << "point " << i;
    removed += before.count(i) - own.size();
  }
  EXPECT_EQ(out.points, R.size());  // every point saw the other sheet
  EXPECT_EQ(out.removed, removed);
}

TEST(LimitNeighborhoodsToMesh, ATighterLimitCutsLongPaths) {
  const double h = 0.1, r = 0.45;
  const Sheets s = two_sheets(12, h, 5.0);  // the sheets are out of each other's reach
  Neighborhoods R = radius_neighborhoods(s.P, {r, 0});
  LimitNeighborhoodsToMeshParams p;
  p.radius = r;
  p.path_factor = 1.0;
  limit_neighborhoods_to_mesh(R, s.P, s.T, p);
  const auto at = [&](int x, int y) { return static_cast<std::uint32_t>(y * s.m + x); };
  const std::set<std::uint32_t> kept = row(R, at(5, 5));
  // (+3, +3): 0.42 away, path 0.3 (along the diagonals): kept.
  EXPECT_TRUE(kept.count(at(8, 8)));
  // (+3, -3): 0.42 away, path 0.6 > r: cut.
  EXPECT_FALSE(kept.count(at(8, 2)));
  // (+4, 0): 0.4 away, path 0.4: kept; (+2, -2): 0.28 away, path 0.4: kept.
  EXPECT_TRUE(kept.count(at(9, 5)));
  EXPECT_TRUE(kept.count(at(7, 3)));
  // (+3, -2): 0.36 away, path 0.5 > r: cut.
  EXPECT_FALSE(kept.count(at(8, 3)));
  // Path lengths are symmetric, so R stays symmetric.
  for (std::size_t i = 0; i < R.size(); ++i)
    for (const std::uint32_t j : row(R, i)) EXPECT_TRUE(row(R, j).count(i)) << i << " " << j;
}

TEST(LimitNeighborhoodsToMesh, NoLimitLeavesRAsItWas) {
  const Sheets s = two_sheets(8, 0.1, 0.2);
  Neighborhoods R = radius_neighborhoods(s.P, {0.35, 0});
  const Neighborhoods before = R;
  LimitNeighborhoodsToMeshParams p;
  p.radius = 0.35;
  p.path_factor = 0.0;
  const LimitNeighborhoodsToMeshResult out = limit_neighborhoods_to_mesh(R, s.P, s.T, p);
  EXPECT_EQ(out.points, 0u);
  EXPECT_EQ(R.offsets, before.offsets);
  EXPECT_EQ(R.indices, before.indices);
}

TEST(LimitNeighborhoodsToMesh, RefusesBadInput) {
  Sheets s = two_sheets(4, 0.1, 0.2);
  Neighborhoods R = radius_neighborhoods(s.P, {0.25, 0});
  LimitNeighborhoodsToMeshParams p;
  p.radius = 0.25;
  p.path_factor = 0.5;  // below r: a neighbor at the rim could never stay
  EXPECT_THROW(limit_neighborhoods_to_mesh(R, s.P, s.T, p), std::invalid_argument);
  p.path_factor = 1.5;
  p.radius = 0.0;
  EXPECT_THROW(limit_neighborhoods_to_mesh(R, s.P, s.T, p), std::invalid_argument);
  p.radius = 0.25;
  s.T(0, 1) = static_cast<std::int32_t>(s.P.rows());
  EXPECT_THROW(limit_neighborhoods_to_mesh(R, s.P, s.T, p), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
