#include "detexture/geometry/estimate_normals.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "test_support.h"

namespace detexture {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance from n to the nearer of +expected and -expected.
double sign_free_error(const Eigen::RowVector3d& n, const Eigen::RowVector3d& expected) {
  return std::min((n - expected).norm(), (n + expected).norm());
}

// Points center + x u + y v on a jittered grid of spacing h in the plane
// spanned by the unit vectors u, v.
Positions plane_grid(const Eigen::RowVector3d& center, const Eigen::RowVector3d& u,
                     const Eigen::RowVector3d& v, int rows, int cols, double h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3 * h, 0.3 * h);
  Positions P(rows * cols, 3);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x = (c - cols / 2) * h + jitter(rng), y = (r - rows / 2) * h + jitter(rng);
      P.row(r * cols + c) = center + x * u + y * v;
    }
  return P;
}

TEST(EstimateNormals, PlaneFarFromOriginGivesPlaneNormal) {
  const Eigen::RowVector3d n0 = Eigen::RowVector3d(1, 2, 3).normalized();
  const Eigen::RowVector3d u = Eigen::RowVector3d(2, -1, 0).normalized(), v = n0.cross(u);
  const Positions P = plane_grid({1000.0, -2000.0, 500.0}, u, v, 40, 40, 0.01, 1);
  const EstimateNormalsResult r = estimate_normals(P, radius_neighborhoods(P, {0.025, 0}));
  EXPECT_EQ(r.degenerate, 0u);
  for (int i = 0; i < P.rows(); ++i) {
    ASSERT_LE(sign_free_error(r.normals.row(i), n0), 1e-9) << "point " << i;
    ASSERT_LE(r.variation(i), 1e-12);
  }
}

// Exactly planar neighborhoods 1 long and 1e-4 wide: Eigen's closed-form
// computeDirect is wrong by up to 90 degrees here; the iterative solver is not.
TEST(EstimateNormals, ElongatedPlanarNeighborhoodsAreAccurate) {
  const Eigen::RowVector3d n0 = Eigen::RowVector3d(-3, 1, 2).normalized();
  const Eigen::RowVector3d u = n0.unitOrthogonal(), v = n0.cross(u);
  Positions P(60, 3);
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 3; ++j) P.row(3 * i + j) = (0.05 * i) * u + (1e-4 * j) * v;
  const EstimateNormalsResult r = estimate_normals(P, knn_neighborhoods(P, 60));
  EXPECT_EQ(r.degenerate, 0u);
  for (int i = 0; i < P.rows(); ++i) ASSERT_LE(sign_free_error(r.normals.row(i), n0), 1e-6);
}

TEST(EstimateNormals, SphereNormalsAreRadial) {
  const Eigen::RowVector3d center(3.0, -1.0, 2.0);
  const Positions P = test::fibonacci_sphere(20000, 1.0, center).P;
  const EstimateNormalsResult r = estimate_normals(P, knn_neighborhoods(P, 16));
  EXPECT_EQ(r.degenerate, 0u);
  const double one_degree = std::cos(kPi / 180.0);
  for (int i = 0; i < P.rows(); ++i) {
    const Eigen::RowVector3d radial = (P.row(i) - center).normalized();
    ASSERT_NEAR(r.normals.row(i).norm(), 1.0, 1e-12);
    ASSERT_GE(std::abs(r.normals.row(i).dot(radial)), one_degree) << "point " << i;
  }
}

// Points farther than the radius from every other face see only their own
// face, so their normal is the face normal.
TEST(EstimateNormals, CubeFacesAwayFromEdgesGiveFaceNormals) {
  const test::BumpyPlane cube = test::cube_faces(20);
  const Positions& P = cube.P;
  const Normals& face_normal = cube.N;
  const double radius = 0.08;
  const EstimateNormalsResult r = estimate_normals(P, radius_neighborhoods(P, {radius, 0}));
  EXPECT_EQ(r.degenerate, 0u);
  int checked = 0;
  for (int i = 0; i < P.rows(); ++i) {
    const Eigen::RowVector3d in_face = P.row(i).cwiseAbs() - 0.5 * face_normal.row(i).cwiseAbs();
    if (in_face.maxCoeff() >= 0.5 - radius) continue;
    ASSERT_LE(sign_free_error(r.normals.row(i), face_normal.row(i)), 1e-9) << "point " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 6 * 16 * 16);  // 16 of 20 cell centers per axis: |coordinate| <= 0.375
}

TEST(EstimateNormals, SurfaceVariationOfKnownNeighborhoods) {
  // Corners of a 6 x 4 x 2 box: covariance diag(9, 4, 1), so the normal is z
  // and the variation 1 / 14.
  Positions box(8, 3);
  for (int i = 0; i < 8; ++i) box.row(i) << (i & 1 ? 3 : -3), (i & 2 ? 2 : -2), (i & 4 ? 1 : -1);
  const EstimateNormalsResult r = estimate_normals(box, knn_neighborhoods(box, 8));
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(r.variation(i), 1.0 / 14.0, 1e-14);
    EXPECT_LE(sign_free_error(r.normals.row(i), Eigen::RowVector3d(0, 0, 1)), 1e-12);
  }
  // A regular tetrahedron: isotropic covariance, the largest variation, 1/3.
  Positions tetrahedron(4, 3);
  tetrahedron << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  const EstimateNormalsResult t = estimate_normals(tetrahedron, knn_neighborhoods(tetrahedron, 4));
  EXPECT_EQ(t.degenerate, 0u);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(t.variation(i), 1.0 / 3.0, 1e-14);
}

TEST(EstimateNormals, DegeneratePointsGetZeroNormalsAndAreCounted) {
  // With radius 0.05: a plane patch (fine), 5 isolated points (1 neighbor),
  // a pair (2 neighbors), a line of 10 points 0.01 apart (collinear) and 4
  // copies of one point (coincident): 5 + 2 + 10 + 4 = 21 degenerate.
  const Positions patch = plane_grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, 10, 0.01, 2);
  std::vector<Eigen::RowVector3d> points;
  for (int i = 0; i < patch.rows(); ++i) points.push_back(patch.row(i));
  for (int i = 0; i < 5; ++i) points.emplace_back(10.0 + i, 0.0, 0.0);
  points.emplace_back(0.0, 10.0, 0.0);
  points.emplace_back(0.0, 10.03, 0.0);
  for (int i = 0; i < 10; ++i) points.emplace_back(0.0, -10.0 + 0.01 * i, 0.01 * i);
  for (int i = 0; i < 4; ++i) points.emplace_back(-10.0, -10.0, -10.0);
  Positions P(points.size(), 3);
  for (std::size_t i = 0; i < points.size(); ++i) P.row(i) = points[i];

  const EstimateNormalsResult r = estimate_normals(P, radius_neighborhoods(P, {0.05, 0}));
  EXPECT_EQ(r.degenerate, 21u);
  for (int i = 0; i < P.rows(); ++i) {
    if (i < patch.rows())
      EXPECT_LE(sign_free_error(r.normals.row(i), Eigen::RowVector3d(0, 0, 1)), 1e-12);
    else
      EXPECT_EQ(r.normals.row(i).squaredNorm(), 0.0) << "point " << i;
  }
}

TEST(EstimateNormals, SameForAnyThreadCountAndReportsProgress) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  Positions P = test::fibonacci_sphere(30000, 1.0).P;
  for (int i = 0; i < P.rows(); ++i) P.row(i) *= 1.0 + noise(rng);
  const Neighborhoods N = knn_neighborhoods(P, 12);
  omp_set_num_threads(1);
  const EstimateNormalsResult a = estimate_normals(P, N);
  omp_set_num_threads(2);
  std::vector<double> reported;
  const EstimateNormalsResult b = estimate_normals(P, N, [&](double f) { reported.push_back(f); });
  EXPECT_TRUE(a.normals == b.normals);
  EXPECT_TRUE(a.variation == b.variation);
  EXPECT_EQ(a.degenerate, b.degenerate);
  ASSERT_FALSE(reported.empty());
  EXPECT_LE(reported.size(), 101u);
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_EQ(reported.back(), 1.0);
}

TEST(EstimateNormals, RejectsNeighborhoodsOfAnotherCloud) {
  const Positions P = test::fibonacci_sphere(100, 1.0).P;
  const Positions Q = test::fibonacci_sphere(50, 1.0).P;
  EXPECT_THROW(estimate_normals(P, knn_neighborhoods(Q, 5)), std::invalid_argument);
}

TEST(ReestimateZeroNormals, FillsZerosToAgreeWithNeighbors) {
  const Eigen::RowVector3d n0 = Eigen::RowVector3d(1, -2, 2) / 3.0;
  const Eigen::RowVector3d u = n0.unitOrthogonal(), v = n0.cross(u);
  const Positions P = plane_grid({5, 5, 5}, u, v, 30, 30, 0.01, 3);
  const Neighborhoods N = radius_neighborhoods(P, {0.025, 0});
  for (const double side : {1.0, -1.0}) {
    Normals normals = (2.0 * side * n0).replicate(P.rows(), 1);  // any length will do
    std::size_t zeros = 0;
    for (int i = 0; i < P.rows(); i += 7, ++zeros) normals.row(i).setZero();
    std::size_t reestimated = 0;
    const Normals result = reestimate_zero_normals(P, normals, N, &reestimated);
    EXPECT_EQ(reestimated, zeros);
    for (int i = 0; i < P.rows(); ++i) {
      if (i % 7 == 0)
        ASSERT_LE((result.row(i) - side * n0).norm(), 1e-9) << "point " << i;
      else
        ASSERT_TRUE(result.row(i) == normals.row(i));
    }
  }
}

TEST(ReestimateZeroNormals, LeavesZeroWhatCannotBeResolved) {
  // A patch with normals, a patch without any, and an isolated point: only
  // the patch with normals can orient its zeros.
  const Positions a = plane_grid({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, 10, 0.01, 4);
  const Positions b = plane_grid({5, 0, 0}, {1, 0, 0}, {0, 1, 0}, 10, 10, 0.01, 5);
  Positions P(201, 3);
  P << a, b, Eigen::RowVector3d(-5, 0, 0);
  Normals normals = Normals::Zero(201, 3);
  for (int i = 0; i < 100; i += 2) normals.row(i) << 0, 0, -1;
  std::size_t reestimated = 0;
  const Normals result =
      reestimate_zero_normals(P, normals, radius_neighborhoods(P, {0.025, 0}), &reestimated);
  EXPECT_EQ(reestimated, 50u);
  for (int i = 0; i < 100; ++i)
    EXPECT_LE((result.row(i) - Eigen::RowVector3d(0, 0, -1)).norm(), 1e-12);
  for (int i = 100; i < 201; ++i) EXPECT_EQ(result.row(i).squaredNorm(), 0.0);
}

}  // namespace
}  // namespace detexture
