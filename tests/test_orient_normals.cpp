#include "detexture/geometry/orient_normals.h"

#include "detexture/geometry/radius_neighborhoods.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "detexture/geometry/estimate_normals.h"
#include "test_support.h"

namespace detexture {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Each normal negated with probability 1/2.
Normals random_signs(const Normals& normals, unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution flip(0.5);
  Normals result = normals;
  for (int i = 0; i < result.rows(); ++i)
    if (flip(rng)) result.row(i) *= -1.0;
  return result;
}

// Exactly round(fraction * #normals) normals negated, chosen at random.
Normals flip_fraction(const Normals& normals, double fraction, unsigned seed) {
  std::vector<int> order(normals.rows());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  Normals result = normals;
  const int count = static_cast<int>(std::lround(fraction * normals.rows()));
  for (int i = 0; i < count; ++i) result.row(order[i]) *= -1.0;
  return result;
}

std::size_t count_facing_inward(const Positions& P, const Normals& normals,
                                const Eigen::RowVector3d& center) {
  std::size_t inward = 0;
  for (int i = 0; i < P.rows(); ++i)
    if (normals.row(i).dot(P.row(i) - center) < 0.0) ++inward;
  return inward;
}

TEST(OrientNormals, SphereFacesOutward) {
  const Eigen::RowVector3d center(1.0, 2.0, 3.0);
  const Positions P = test::fibonacci_sphere(10000, 2.0, center).P;
  const Normals unoriented =
      random_signs(estimate_normals(P, knn_neighborhoods(P, 12)).normals, 11);
  const OrientNormalsResult r = orient_normals(P, unoriented, knn_neighborhoods(P, 10));
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.cross_sheet_edges, 0u);
  EXPECT_EQ(r.flipped, count_facing_inward(P, unoriented, center));
  EXPECT_EQ(count_facing_inward(P, r.normals, center), 0u);
}

TEST(OrientNormals, TorusFacesAwayFromItsCoreCircle) {
  // Torus around the z axis: core circle of radius 1, tube radius 0.3,
  // sampled on a jittered (u, v) grid; outward = away from the core circle.
  const double R = 1.0, r = 0.3;
  const int nu = 240, nv = 60;
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  Positions P(nu * nv, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * (i + jitter(rng)) / nu, v = 2 * kPi * (j + jitter(rng)) / nv;
      P.row(i * nv + j) << (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
          r * std::sin(v);
    }
  const Normals unoriented =
      random_signs(estimate_normals(P, knn_neighborhoods(P, 12)).normals, 17);
  const OrientNormalsResult result = orient_normals(P, unoriented, knn_neighborhoods(P, 10));
  EXPECT_EQ(result.components, 1u);
  std::size_t inward = 0;
  for (int i = 0; i < P.rows(); ++i) {
    Eigen::RowVector3d core(P(i, 0), P(i, 1), 0.0);
    core *= R / core.norm();
    if (result.normals.row(i).dot(P.row(i) - core) <= 0.0) ++inward;
  }
  EXPECT_EQ(inward, 0u);
}

// With exact face normals, neighbors across a cube edge are perpendicular:
// n_i . n_j = 0 says nothing, but the normals projected across the chord do.
TEST(OrientNormals, CubeWithExactFaceNormalsFacesOutward) {
  const test::BumpyPlane cube = test::cube_faces(20);
  const Positions& P = cube.P;
  const Normals& face_normal = cube.N;
  const OrientNormalsResult r =
      orient_normals(P, random_signs(face_normal, 19), knn_neighborhoods(P, 10));
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.cross_sheet_edges, 0u);
  EXPECT_TRUE(r.normals == face_normal);
}

TEST(OrientNormals, CubeWithPcaNormalsFacesOutward) {
  const test::BumpyPlane cube = test::cube_faces(20);
  const Positions& P = cube.P;
  const Normals& face_normal = cube.N;
  const EstimateNormalsResult e = estimate_normals(P, radius_neighborhoods(P, {0.08, 0}));
  ASSERT_EQ(e.degenerate, 0u);
  const OrientNormalsResult r =
      orient_normals(P, random_signs(e.normals, 23), knn_neighborhoods(P, 10));
  EXPECT_EQ(count_facing_inward(P, r.normals, {0, 0, 0}), 0u);
}

// A closed plate 1 x 1 x 0.02: big faces sampled every 0.05 (2.5 times the
// thickness), the rim by one row of points at mid-height. Every point's
// nearest neighbor is on the other side, so k-NN edges cross the sheet and
// cost nothing under Hoppe's 1 - |n_i . n_j|; the tree must go around the rim.
TEST(OrientNormals, ThinPlateFacesAwayFromItsMidPlane) {
  const int m = 20;
  const double h = 1.0 / m, half_thickness = 0.01;
  std::vector<Eigen::RowVector3d> points, normals;
  for (int side = -1; side <= 1; side += 2)
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b) {
        points.emplace_back((a + 0.5) * h - 0.5, (b + 0.5) * h - 0.5, side * half_thickness);
        normals.emplace_back(0.0, 0.0, side);
      }
  const int faces = static_cast<int>(points.size());
  for (int axis = 0; axis < 2; ++axis)
    for (int side = -1; side <= 1; side += 2)
      for (int a = 0; a < m; ++a) {
        Eigen::RowVector3d p(0, 0, 0), n(0, 0, 0);
        p(axis) = 0.5 * side;
        p(1 - axis) = (a + 0.5) * h - 0.5;
        n(axis) = side;
        points.push_back(p);
        normals.push_back(n);
      }
  Positions P(points.size(), 3);
  Normals outward(points.size(), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    P.row(i) = points[i];
    outward.row(i) = normals[i];
  }

  for (const int k : {10, 20, 30}) {
    const Neighborhoods N = knn_neighborhoods(P, k);
    for (int i = 0; i < faces; ++i)  // the nearest other point is across the sheet
      ASSERT_NEAR(std::abs(P(N.begin(i)[1], 2) - P(i, 2)), 2 * half_thickness, 1e-15);
    const OrientNormalsResult r = orient_normals(P, random_signs(outward, 29), N);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(r.cross_sheet_edges, 0u);
    for (int i = 0; i < P.rows(); ++i)
      ASSERT_TRUE(r.normals.row(i) == outward.row(i)) << "k = " << k << ", point " << i;
  }
}

TEST(OrientNormals, ZeroNormalsStayZeroAndAreBypassed) {
  const Positions P = test::fibonacci_sphere(5000, 1.0).P;
  Normals unoriented = random_signs(P, 31);  // radial on the unit sphere
  for (int i = 0; i < P.rows(); i += 5) unoriented.row(i).setZero();
  const OrientNormalsResult r = orient_normals(P, unoriented, knn_neighborhoods(P, 10));
  EXPECT_EQ(r.components, 1u);
  for (int i = 0; i < P.rows(); ++i) {
    if (i % 5 == 0)
      ASSERT_EQ(r.normals.row(i).squaredNorm(), 0.0);
    else
      ASSERT_TRUE(r.normals.row(i) == P.row(i)) << "point " << i;
  }
}

TEST(OrientNormals, SeparateShapesAreSeparateComponents) {
  const Eigen::RowVector3d a(-5, 0, 0), b(5, 0, 0);
  Positions P(4000, 3);
  P << test::fibonacci_sphere(2000, 1.0, a).P, test::fibonacci_sphere(2000, 2.0, b).P;
  Normals radial(4000, 3);
  for (int i = 0; i < 4000; ++i) radial.row(i) = (P.row(i) - (i < 2000 ? a : b)).normalized();
  const OrientNormalsResult r =
      orient_normals(P, random_signs(radial, 37), knn_neighborhoods(P, 10));
  EXPECT_EQ(r.components, 2u);
  EXPECT_TRUE(r.normals == radial);
}

// A 41 x 41 grid of z = a (x² - y²) on [-1, 1]², with its exact normals
// (-2 a x, 2 a y, 1) / |.|, as given by synth's saddle.
std::pair<Positions, Normals> saddle(double a) {
  const int m = 41;
  Positions P(m * m, 3);
  Normals up(m * m, 3);
  for (int i = 0; i < m * m; ++i) {
    const double x = -1.0 + 2.0 * (i % m) / (m - 1), y = -1.0 + 2.0 * (i / m) / (m - 1);
    P.row(i) << x, y, a * (x * x - y * y);
    up.row(i) = Eigen::RowVector3d(-2.0 * a * x, 2.0 * a * y, 1.0).normalized();
  }
  return {P, up};
}

// Open sheets without a convex side face up (rule 2 of orient_normals.h's
// "Side"): the flux Σ n·(p - c) of a plane and of a symmetric saddle is 0.
// Before, their farthest point (a corner, where n·(p - c) = 0) could not
// tell, and they kept the sign of the input normal where the tree started.
TEST(OrientNormals, FlatOpenSheetsFaceUp) {
  for (const double a : {0.0, 0.3}) {
    const auto [P, up] = saddle(a);
    const OrientNormalsResult r = orient_normals(P, random_signs(up, 61), knn_neighborhoods(P, 10));
    EXPECT_EQ(r.components, 1u);
    EXPECT_TRUE(r.normals == up) << "a = " << a;
    EXPECT_TRUE(orient_normals(P, -up, knn_neighborhoods(P, 10)).normals == up) << "a = " << a;
  }
}

// A cap of the unit sphere facing down, as one tile of a closed scan: its
// convex side is below it (rule 1), so it faces down and out, not up. Half-angle
// 40 degrees: flux ratio about 0.5, far from the threshold 0.05.
TEST(OrientNormals, CapFacesItsConvexSideBeforeUp) {
  const Positions sphere = test::fibonacci_sphere(4000, 1.0).P;
  std::vector<int> keep;
  for (int i = 0; i < sphere.rows(); ++i)
    if (sphere(i, 2) < -std::cos(40.0 * kPi / 180.0)) keep.push_back(i);
  Positions P(keep.size(), 3);
  for (std::size_t i = 0; i < keep.size(); ++i) P.row(i) = sphere.row(keep[i]);
  const Normals outward = P;  // radial on the unit sphere
  const OrientNormalsResult r =
      orient_normals(P, random_signs(outward, 67), knn_neighborhoods(P, 10));
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(count_facing_inward(P, r.normals, {0, 0, 0}), 0u);
}

// A chosen side: an axis direction turns a sheet to face it (a saddle, and
// a plane turned to x = 0, which rule 2 of Auto leaves to the farthest point);
// outward and inward go by the flux.
TEST(OrientNormals, ChosenSideIsFaced) {
  const auto [P, up] = saddle(0.3);
  const Neighborhoods N = knn_neighborhoods(P, 10);
  OrientNormalsParams params;
  params.side = NormalSide::MinusZ;
  EXPECT_TRUE(orient_normals(P, random_signs(up, 71), N, params).normals == -up);
  params.side = NormalSide::PlusZ;
  EXPECT_TRUE(orient_normals(P, random_signs(up, 73), N, params).normals == up);

  auto [wall, facing_x] = saddle(0.0);
  wall.col(0).swap(wall.col(2));
  facing_x.col(0).swap(facing_x.col(2));
  const Neighborhoods W = knn_neighborhoods(wall, 10);
  params.side = NormalSide::PlusX;
  EXPECT_TRUE(orient_normals(wall, -facing_x, W, params).normals == facing_x);
  params.side = NormalSide::MinusX;
  EXPECT_TRUE(orient_normals(wall, facing_x, W, params).normals == -facing_x);

  const Positions sphere = test::fibonacci_sphere(2000, 1.0).P;
  const Neighborhoods S = knn_neighborhoods(sphere, 10);
  const Normals outward = sphere;
  params.side = NormalSide::Inward;
  EXPECT_TRUE(orient_normals(sphere, random_signs(outward, 83), S, params).normals == -outward);
  params.side = NormalSide::Outward;
  EXPECT_TRUE(orient_normals(sphere, random_signs(outward, 89), S, params).normals == outward);
  params.side = static_cast<NormalSide>(42);
  EXPECT_THROW(orient_normals(sphere, outward, S, params), std::invalid_argument);
}

// Grid points' 5 nearest neighbors are themselves and their grid neighbors,
// 1 away; a point 0.9 above a cell center (1.14 from its corners) is nobody's
// neighbor but has neighbors. Treated as undirected, all is one component.
TEST(OrientNormals, KnnGraphIsTreatedAsUndirected) {
  Positions P(101, 3);
  for (int i = 0; i < 100; ++i) P.row(i) << i % 10, i / 10, 0;
  P.row(100) << 4.5, 4.5, 0.9;
  Normals unoriented = Eigen::RowVector3d(0, 0, 1).replicate(101, 1);
  unoriented.row(100) *= -1.0;
  const Neighborhoods N = knn_neighborhoods(P, 5);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(std::count(N.begin(i), N.end(i), 100u), 0);
  const OrientNormalsResult r = orient_normals(P, unoriented, N);
  EXPECT_EQ(r.components, 1u);
  // The lone point is reached only by chords steep to both tangent planes.
  EXPECT_EQ(r.cross_sheet_edges, 1u);
  for (int i = 0; i < 101; ++i) ASSERT_TRUE(r.normals.row(i) == r.normals.row(0));
}

TEST(OrientNormals, SameForAnyThreadCount) {
  std::mt19937 rng(41);
  std::normal_distribution<double> noise(0.0, 0.005);
  Positions P = test::fibonacci_sphere(30000, 1.0).P;
  for (int i = 0; i < P.rows(); ++i) P.row(i) *= 1.0 + noise(rng);
  const Normals unoriented =
      random_signs(estimate_normals(P, knn_neighborhoods(P, 12)).normals, 43);
  omp_set_num_threads(1);
  const OrientNormalsResult a = orient_normals(P, unoriented, knn_neighborhoods(P, 10));
  omp_set_num_threads(2);
  const OrientNormalsResult b = orient_normals(P, unoriented, knn_neighborhoods(P, 10));
  EXPECT_TRUE(a.normals == b.normals);
  EXPECT_EQ(a.flipped, b.flipped);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(count_facing_inward(P, a.normals, {0, 0, 0}), 0u);
}

TEST(OrientNormals, RejectsBadInput) {
  const Positions P = test::fibonacci_sphere(100, 1.0).P;
  const Neighborhoods N = knn_neighborhoods(P, 5);
  EXPECT_THROW(orient_normals(P, P.topRows(50), N), std::invalid_argument);
  EXPECT_THROW(orient_normals(P.topRows(50), P.topRows(50), N), std::invalid_argument);
  OrientNormalsParams params;
  params.cross_sheet_angle = 0.0;
  EXPECT_THROW(orient_normals(P, P, N, params), std::invalid_argument);
  params.cross_sheet_angle = 120.0;
  EXPECT_THROW(orient_normals(P, P, N, params), std::invalid_argument);
}

TEST(OrientationInconsistency, ConsistentFieldsScoreZero) {
  const Positions sphere = test::fibonacci_sphere(20000, 1.0).P;
  EXPECT_EQ(orientation_inconsistency(sphere, knn_neighborhoods(sphere, 10)), 0.0);
  // Neighbors across the cube's edges are perpendicular, hence not compared.
  const test::BumpyPlane cube = test::cube_faces(20);
  EXPECT_EQ(orientation_inconsistency(cube.N, knn_neighborhoods(cube.P, 10)), 0.0);
}

// A pair disagrees when exactly one of its normals was flipped: 2 f (1 - f).
TEST(OrientationInconsistency, RandomFlipsScoreTwoFTimesOneMinusF) {
  const Positions P = test::fibonacci_sphere(20000, 1.0).P;
  const Neighborhoods N = knn_neighborhoods(P, 10);
  const double ten_percent = orientation_inconsistency(flip_fraction(P, 0.10, 47), N);
  EXPECT_NEAR(ten_percent, 0.18, 0.01);
  EXPECT_GT(ten_percent, 10 * kInconsistentOrientationThreshold);
  const double one_percent = orientation_inconsistency(flip_fraction(P, 0.01, 53), N);
  EXPECT_NEAR(one_percent, 0.0198, 0.003);
  EXPECT_GT(one_percent, kInconsistentOrientationThreshold);
  // Only the nearest members of larger neighborhoods: the same expectation,
  // and exactly the k-NN score when the rows are the k-NN rows.
  const Normals flipped = flip_fraction(P, 0.10, 47);
  const Neighborhoods R = radius_neighborhoods(P, {0.12, 0});
  ASSERT_GT(neighborhood_stats(R, 0).min, 10u);
  EXPECT_NEAR(orientation_inconsistency(flipped, R, 10), 0.18, 0.01);
  EXPECT_EQ(orientation_inconsistency(flipped, knn_neighborhoods(P, 30), 10), ten_percent);
}

TEST(OrientationInconsistency, OrientedPcaNormalsScoreZero) {
  const Positions P = test::fibonacci_sphere(20000, 1.0).P;
  const Normals unoriented =
      random_signs(estimate_normals(P, knn_neighborhoods(P, 12)).normals, 59);
  const Neighborhoods N = knn_neighborhoods(P, 10);
  EXPECT_NEAR(orientation_inconsistency(unoriented, N), 0.5, 0.02);
  EXPECT_EQ(orientation_inconsistency(orient_normals(P, unoriented, N).normals, N), 0.0);
}

}  // namespace
}  // namespace detexture
