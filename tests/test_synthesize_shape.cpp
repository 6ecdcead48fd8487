#include "detexture/eval/synthesize_shape.h"

#include <gtest/gtest.h>
#include <omp.h>
#include <sys/wait.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "detexture/io/read_point_cloud.h"

namespace detexture {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
const BaseShape kShapes[] = {BaseShape::Sphere,    BaseShape::Cube,    BaseShape::Cylinder,
                             BaseShape::Torus,     BaseShape::Pyramid, BaseShape::Plane,
                             BaseShape::Ellipsoid, BaseShape::Saddle,  BaseShape::Knot,
                             BaseShape::Blob,      BaseShape::Disc,    BaseShape::Mesh};
const BaseShape kNewShapes[] = {BaseShape::Ellipsoid, BaseShape::Saddle, BaseShape::Knot,
                                BaseShape::Blob,      BaseShape::Disc,   BaseShape::Mesh};
const TextureKind kTextures[] = {
    TextureKind::Bumps,    TextureKind::Domes,    TextureKind::Scales,    TextureKind::Waves,
    TextureKind::VGrooves, TextureKind::UGrooves, TextureKind::MultiScale};

// The pyramid's faces as planes n.x = d (outward normals), written out from
// its definition: base z = -0.5, apex (0, 0, 0.5), base corners (+-0.5, +-0.5).
struct FacePlane {
  Vector3d n;
  double d;
};
std::vector<FacePlane> pyramid_planes() {
  std::vector<FacePlane> planes = {{Vector3d(0, 0, -1), 0.5}};
  for (const Vector3d& side :
       {Vector3d(2, 0, 1), Vector3d(-2, 0, 1), Vector3d(0, 2, 1), Vector3d(0, -2, 1)})
    planes.push_back({side.normalized(), 0.5 / side.norm()});  // through the apex (0, 0, 0.5)
  return planes;
}

// The new shapes, written out from their definitions in the header and the docs.
const Vector3d kAxes(0.5, 0.32, 0.2);  // ellipsoid
constexpr double kSaddle = 0.6;        // z = 0.6 (x^2 - y^2)
constexpr double kTube = 0.07;         // knot

// The trefoil (0.43/3) (sin t + 2 sin 2t, cos t - 2 cos 2t, -1.5 sin 3t).
Vector3d trefoil(double t) {
  return 0.43 / 3 *
         Vector3d(std::sin(t) + 2 * std::sin(2 * t), std::cos(t) - 2 * std::cos(2 * t),
                  -1.5 * std::sin(3 * t));
}
// The point of the curve nearest to x: the best of 20000 parameters, then
// golden-section search around it.
Vector3d nearest_on_trefoil(const Vector3d& x) {
  constexpr int n = 20000;
  static const std::vector<Vector3d> table = [] {
    std::vector<Vector3d> points(n);
    for (int i = 0; i < n; ++i) points[i] = trefoil(2 * kPi * i / n);
    return points;
  }();
  double best_t = 0.0, best = 1e300;
  for (int i = 0; i < n; ++i) {
    const double d = (table[i] - x).squaredNorm();
    if (d < best) best = d, best_t = 2 * kPi * i / n;
  }
  double lo = best_t - 2 * kPi / n, hi = best_t + 2 * kPi / n;
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 100; ++i) {
    const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
    if ((trefoil(a) - x).squaredNorm() < (trefoil(b) - x).squaredNorm())
      hi = b;
    else
      lo = a;
  }
  return trefoil(0.5 * (lo + hi));
}

struct Limb {
  Vector3d axis;
  double length, width;
};
const Limb kLimbs[] = {{Vector3d(1.0, 0.1, 0.15).normalized(), 0.25, 0.05},
                       {Vector3d(-0.45, 0.85, 0.2).normalized(), 0.2, 0.04},
                       {Vector3d(-0.5, -0.8, 0.1).normalized(), 0.22, 0.05},
                       {Vector3d(0.3, -0.6, -0.7).normalized(), 0.15, 0.06},
                       {Vector3d(-0.1, 0.25, 0.95).normalized(), 0.12, 0.1},
                       {Vector3d(0.35, 0.7, -0.6).normalized(), 0.1, 0.08}};
double blob_radius(const Vector3d& d) {
  double r = 0.22;
  for (const Limb& l : kLimbs) r += l.length * std::exp((d.dot(l.axis) - 1) / l.width);
  return r;
}

// Disc: sheets z = +-0.03 over rho <= 0.37, rim the outer half of the torus (0.37, 0.03).
bool on_disc_rim(const Vector3d& b) { return b.head<2>().norm() > 0.37; }

// The unit cube as 12 triangles (two per face, counter-clockwise from outside).
std::shared_ptr<const BaseMesh> cube_mesh() {
  auto mesh = std::make_shared<BaseMesh>();
  mesh->vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    mesh->vertices.row(i) << (i & 1 ? 0.5 : -0.5), (i & 2 ? 0.5 : -0.5), (i & 4 ? 0.5 : -0.5);
  mesh->triangles.resize(12, 3);
  mesh->triangles << 0, 2, 3, 0, 3, 1,  // z = -0.5
      4, 5, 7, 4, 7, 6,                 // z = +0.5
      0, 1, 5, 0, 5, 4,                 // y = -0.5
      2, 6, 7, 2, 7, 3,                 // y = +0.5
      0, 4, 6, 0, 6, 2,                 // x = -0.5
      1, 3, 7, 1, 7, 5;                 // x = +0.5
  return mesh;
}

// Distance from x to the analytic base surface, for points on or near it.
double distance_to_base(BaseShape shape, const Vector3d& x) {
  if (shape == BaseShape::Mesh) shape = BaseShape::Cube;  // the tests' mesh is the unit cube
  switch (shape) {
    case BaseShape::Mesh:
      break;
    case BaseShape::Sphere:
      return std::abs(x.norm() - 0.5);
    case BaseShape::Cube: {
      const Vector3d q = x.cwiseAbs() - Vector3d::Constant(0.5);
      return std::abs(q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0));
    }
    case BaseShape::Cylinder: {
      const double a = x.head<2>().norm() - 0.5, b = std::abs(x.z()) - 0.5;
      return std::abs(std::min(std::max(a, b), 0.0) + Eigen::Vector2d(a, b).cwiseMax(0.0).norm());
    }
    case BaseShape::Torus:
      return std::abs(std::hypot(x.head<2>().norm() - 0.35, x.z()) - 0.15);
    case BaseShape::Pyramid: {
      double m = -1e300;
      for (const FacePlane& p : pyramid_planes()) m = std::max(m, p.n.dot(x) - p.d);
      return std::abs(m);
    }
    case BaseShape::Plane:
      return std::abs(x.z()) + std::max(0.0, std::max(std::abs(x.x()), std::abs(x.y())) - 0.5);
    case BaseShape::Ellipsoid: {  // |F| / |grad F|, F = sum x_i^2 / a_i^2 - 1: first order
      const Vector3d q = x.cwiseQuotient(kAxes);
      return std::abs(q.squaredNorm() - 1) / (2 * q.cwiseQuotient(kAxes).norm());
    }
    case BaseShape::Saddle:
      return std::abs(x.z() - kSaddle * (x.x() * x.x() - x.y() * x.y())) /
                 std::sqrt(1 + 4 * kSaddle * kSaddle * x.head<2>().squaredNorm()) +
             std::max(0.0, x.head<2>().norm() - 0.5);
    case BaseShape::Knot:
      return std::abs((x - nearest_on_trefoil(x)).norm() - kTube);
    case BaseShape::Blob:  // radial offset, an upper bound of the distance
      return std::abs(x.norm() - blob_radius(x.normalized()));
    case BaseShape::Disc: {
      const double rho = x.head<2>().norm();
      if (rho <= 0.37) return std::abs(std::abs(x.z()) - 0.03);
      return std::abs(std::hypot(rho - 0.37, x.z()) - 0.03);
    }
  }
  return 1e300;
}

// Outward normal of the base at a point b on it, and the projection of a
// nearby point onto the same smooth piece as b.
Vector3d base_normal(BaseShape shape, const Vector3d& b) {
  if (shape == BaseShape::Mesh) shape = BaseShape::Cube;  // the tests' mesh is the unit cube
  switch (shape) {
    case BaseShape::Mesh:
      break;
    case BaseShape::Sphere:
      return b.normalized();
    case BaseShape::Cube: {
      int a = 0;
      b.cwiseAbs().maxCoeff(&a);
      return Vector3d::Unit(a) * (b[a] > 0 ? 1.0 : -1.0);
    }
    case BaseShape::Cylinder:
      if (std::abs(b.head<2>().norm() - 0.5) < std::abs(std::abs(b.z()) - 0.5))
        return Vector3d(b.x(), b.y(), 0).normalized();
      return Vector3d(0, 0, b.z() > 0 ? 1.0 : -1.0);
    case BaseShape::Torus: {
      const Vector3d c = 0.35 * Vector3d(b.x(), b.y(), 0).normalized();
      return (b - c).normalized();
    }
    case BaseShape::Pyramid: {
      const auto planes = pyramid_planes();
      const auto best = std::min_element(planes.begin(), planes.end(), [&](auto& p, auto& q) {
        return std::abs(p.n.dot(b) - p.d) < std::abs(q.n.dot(b) - q.d);
      });
      return best->n;
    }
    case BaseShape::Plane:
      return Vector3d::UnitZ();
    case BaseShape::Ellipsoid:
      return b.cwiseQuotient(kAxes.cwiseProduct(kAxes)).normalized();
    case BaseShape::Saddle:
      return Vector3d(-2 * kSaddle * b.x(), 2 * kSaddle * b.y(), 1).normalized();
    case BaseShape::Knot:
      return (b - nearest_on_trefoil(b)).normalized();
    case BaseShape::Blob: {
      // Central differences of X(d) = r(d) d along two directions normal to b.
      const Vector3d d = b.normalized(), u = d.unitOrthogonal(), v = d.cross(u);
      const double e = 1e-6;
      auto X = [](const Vector3d& q) {
        return Vector3d(blob_radius(q.normalized()) * q.normalized());
      };
      return (X(d + e * u) - X(d - e * u)).cross(X(d + e * v) - X(d - e * v)).normalized();
    }
    case BaseShape::Disc: {
      if (!on_disc_rim(b)) return Vector3d(0, 0, b.z() > 0 ? 1 : -1);
      const Vector3d c = 0.37 * Vector3d(b.x(), b.y(), 0).normalized();
      return (b - c).normalized();
    }
  }
  return Vector3d::Zero();
}

Vector3d project_like(BaseShape shape, const Vector3d& b, const Vector3d& x) {
  const Vector3d n = base_normal(shape, b);
  switch (shape) {
    case BaseShape::Sphere:
      return 0.5 * x.normalized();
    case BaseShape::Torus: {
      const Vector3d c = 0.35 * Vector3d(x.x(), x.y(), 0).normalized();
      return c + 0.15 * (x - c).normalized();
    }
    case BaseShape::Ellipsoid:
      return x / x.cwiseQuotient(kAxes).norm();
    case BaseShape::Saddle:
      return Vector3d(x.x(), x.y(), kSaddle * (x.x() * x.x() - x.y() * x.y()));
    case BaseShape::Knot: {
      const Vector3d c = nearest_on_trefoil(x);
      return c + kTube * (x - c).normalized();
    }
    case BaseShape::Blob:
      return blob_radius(x.normalized()) * x.normalized();
    case BaseShape::Disc:
      if (on_disc_rim(b)) {
        const Vector3d c = 0.37 * Vector3d(x.x(), x.y(), 0).normalized();
        return c + 0.03 * (x - c).normalized();
      }
      return x - (x - b).dot(n) * n;
    case BaseShape::Cylinder:
      if (std::abs(n.z()) < 0.5) {
        const Eigen::Vector2d r = 0.5 * x.head<2>().normalized();
        return Vector3d(r.x(), r.y(), x.z());
      }
      [[fallthrough]];
    default:
      return x - (x - b).dot(n) * n;  // flat pieces: the plane through b
  }
}

SynthParams params_for(BaseShape shape, TextureKind texture, TextureLayout layout, int points) {
  SynthParams p;
  p.shape = shape;
  p.texture = texture;
  p.layout = layout;
  p.points = points;
  p.ground_truth_points = points;
  if (shape == BaseShape::Mesh) p.mesh = cube_mesh();
  return p;
}

TEST(SynthesizeShape, SameSeedSameCloudDifferentSeedDifferentCloud) {
  SynthParams p = params_for(BaseShape::Torus, TextureKind::Scales, TextureLayout::Dense, 5000);
  p.noise = 0.002;
  p.mixed_signs = true;
  const SynthesizedShape a = synthesize_shape(p), b = synthesize_shape(p);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.texture_heights, b.texture_heights);
  EXPECT_EQ(a.ground_truth_positions, b.ground_truth_positions);
  p.seed = 2;
  const SynthesizedShape c = synthesize_shape(p);
  EXPECT_NE(a.positions, c.positions);
  EXPECT_NE(a.texture_heights, c.texture_heights);
  EXPECT_NE(a.ground_truth_positions, c.ground_truth_positions);
}

TEST(SynthesizeShape, IdenticalForAnyThreadCount) {
  SynthParams p =
      params_for(BaseShape::Cube, TextureKind::MultiScale, TextureLayout::Sparse, 20000);
  p.noise = 0.001;
  omp_set_num_threads(1);
  const SynthesizedShape a = synthesize_shape(p);
  omp_set_num_threads(2);
  const SynthesizedShape b = synthesize_shape(p);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.ground_truth_positions, b.ground_truth_positions);
  for (BaseShape shape : kNewShapes) {
    SynthParams q = params_for(shape, TextureKind::Scales, TextureLayout::Dense, 3000);
    q.mixed_signs = true;
    omp_set_num_threads(1);
    const SynthesizedShape c = synthesize_shape(q);
    omp_set_num_threads(2);
    const SynthesizedShape d = synthesize_shape(q);
    EXPECT_EQ(c.positions, d.positions) << base_shape_name(shape);
    EXPECT_EQ(c.normals, d.normals) << base_shape_name(shape);
    EXPECT_EQ(c.ground_truth_positions, d.ground_truth_positions) << base_shape_name(shape);
  }
}

TEST(SynthesizeShape, BaseAndGroundTruthLieOnTheAnalyticShape) {
  for (BaseShape shape : kShapes) {
    const SynthesizedShape s =
        synthesize_shape(params_for(shape, TextureKind::Bumps, TextureLayout::Dense, 4000));
    ASSERT_EQ(s.base_positions.rows(), 4000);
    ASSERT_EQ(s.ground_truth_positions.rows(), 4000);
    // The test's blob normals are finite differences, its knot normals use
    // a golden-section foot point: both good to ~1e-8 only.
    const double normal_tolerance =
        shape == BaseShape::Blob || shape == BaseShape::Knot ? 1e-7 : 1e-12;
    const int count = shape == BaseShape::Knot ? 400 : 4000;  // the test's knot search is slow
    for (Eigen::Index i = 0; i < count; ++i) {
      const Vector3d b = s.base_positions.row(i).transpose();
      ASSERT_LT(distance_to_base(shape, b), 1e-12) << base_shape_name(shape) << " base " << i;
      ASSERT_LT((s.base_normals.row(i).transpose() - base_normal(shape, b)).norm(),
                normal_tolerance)
          << base_shape_name(shape) << " base " << i;
      ASSERT_NEAR(s.base_normals.row(i).norm(), 1.0, 1e-14);
      const Vector3d g = s.ground_truth_positions.row(i).transpose();
      ASSERT_LT(distance_to_base(shape, g), 1e-12) << base_shape_name(shape) << " truth " << i;
      ASSERT_LT((s.ground_truth_normals.row(i).transpose() - base_normal(shape, g)).norm(),
                normal_tolerance)
          << base_shape_name(shape) << " truth " << i;
    }
  }
}

// One test per base shape (these two), so that ctest runs the shapes side
// by side: the sanitizer build spent 133 s and 40 s in them when each was one.
class SynthesizeEachShape : public ::testing::TestWithParam<BaseShape> {};

INSTANTIATE_TEST_SUITE_P(AllShapes, SynthesizeEachShape, ::testing::ValuesIn(kShapes),
                         [](const ::testing::TestParamInfo<BaseShape>& info) {
                           return std::string(base_shape_name(info.param));
                         });

TEST_P(SynthesizeEachShape, DisplacementIsHeightAlongBaseNormal) {
  const BaseShape shape = GetParam();
  for (TextureKind texture : kTextures) {
    const SynthesizedShape s =
        synthesize_shape(params_for(shape, texture, TextureLayout::Sparse, 3000));
    std::size_t textured = 0;
    for (Eigen::Index i = 0; i < 3000; ++i) {
      const double h = s.texture_heights[i];
      const Vector3d p = s.positions.row(i), b = s.base_positions.row(i), n = s.base_normals.row(i);
      ASSERT_LT((p - (b + h * n)).norm(), 1e-15);
      ASSERT_EQ(s.is_texture[i], std::abs(h) > kTextureHeightEpsilon ? 1 : 0);
      // Multi-scale heights add: A + A/3 at most.
      const double peak = texture == TextureKind::MultiScale ? 0.02 * 4 / 3 : 0.02;
      ASSERT_LE(std::abs(h), peak + 1e-15) << "|h| <= A " << base_shape_name(shape) << " "
                                           << texture_kind_name(texture) << " " << b.transpose();
      if (s.is_texture[i]) {
        ++textured;
      } else {
        ASSERT_LT(distance_to_base(shape, p), 1e-12)
            << base_shape_name(shape) << " " << texture_kind_name(texture) << " point " << i;
      }
    }
    EXPECT_GT(textured, 100u) << base_shape_name(shape) << " " << texture_kind_name(texture);
  }
}

// The exact normals against the normals of the surface b -> b + h(b) n(b)
// obtained by central differences along two tangent directions.
TEST_P(SynthesizeEachShape, NormalsMatchFiniteDifferences) {
  constexpr double step = 1e-7;
  const BaseShape shape = GetParam();
  for (TextureKind texture : kTextures)
    for (TextureLayout layout : {TextureLayout::Sparse, TextureLayout::Dense}) {
      SynthParams p = params_for(shape, texture, layout, 300);
      p.mixed_signs = layout == TextureLayout::Dense;
      const SynthesizedShape s = synthesize_shape(p);
      // Rows 5i: the sample itself; 5i+1 .. 5i+4: steps along +-u and +-v.
      Positions Q(5 * s.base_positions.rows(), 3);
      for (Eigen::Index i = 0; i < s.base_positions.rows(); ++i) {
        const Vector3d b = s.base_positions.row(i), n = s.base_normals.row(i);
        const Vector3d u = n.unitOrthogonal(), v = n.cross(u);
        Q.row(5 * i) = b;
        Q.row(5 * i + 1) = project_like(shape, b, b + step * u);
        Q.row(5 * i + 2) = project_like(shape, b, b - step * u);
        Q.row(5 * i + 3) = project_like(shape, b, b + step * v);
        Q.row(5 * i + 4) = project_like(shape, b, b - step * v);
      }
      const TexturedSamples t = evaluate_texture(p, Q);
      const Positions& P = t.positions;
      for (Eigen::Index i = 0; i < s.base_positions.rows(); ++i) {
        ASSERT_EQ(P.row(5 * i), s.positions.row(i)) << "evaluate_texture reproduces samples";
        ASSERT_EQ(t.normals.row(5 * i), s.normals.row(i));
        const Vector3d du = P.row(5 * i + 1) - P.row(5 * i + 2);
        const Vector3d dv = P.row(5 * i + 3) - P.row(5 * i + 4);
        const Vector3d fd = du.cross(dv).normalized(), exact = s.normals.row(i);
        EXPECT_LT(std::atan2(fd.cross(exact).norm(), fd.dot(exact)), 1e-5)
            << base_shape_name(shape) << " " << texture_kind_name(texture) << " "
            << texture_layout_name(layout) << " point " << i << " h " << s.texture_heights[i];
      }
    }
}

// Waves and grooves have closed forms in u = k.b, k = (1,2,3)/sqrt(14): on
// the plane patch, away from the border (e >= 2R, where the window is 1)
// every height is known, and within R of the border it is 0.
TEST(SynthesizeShape, LineTexturesFollowTheirFormulas) {
  const double R = 0.05, A = 0.02;
  const Vector3d k = Vector3d(1, 2, 3).normalized();
  for (TextureKind texture : {TextureKind::Waves, TextureKind::VGrooves, TextureKind::UGrooves})
    for (TextureLayout layout : {TextureLayout::Sparse, TextureLayout::Dense}) {
      const SynthesizedShape s =
          synthesize_shape(params_for(BaseShape::Plane, texture, layout, 5000));
      const double period = layout == TextureLayout::Dense ? 2 * R : 4 * R;
      for (Eigen::Index i = 0; i < 5000; ++i) {
        const Vector3d b = s.base_positions.row(i);
        const double e = 0.5 - std::max(std::abs(b.x()), std::abs(b.y()));
        const double h = s.texture_heights[i];
        if (e <= R) {
          ASSERT_EQ(h, 0.0);
          continue;
        }
        if (e < 2 * R) continue;
        const double u = k.dot(b), v = u - std::round(u / period) * period;
        double expected = 0.0;
        if (std::abs(v) < R) {
          if (texture == TextureKind::Waves) expected = A * (1 + std::cos(kPi * v / R)) / 2;
          if (texture == TextureKind::VGrooves) expected = -A * (1 - std::abs(v) / R);
          if (texture == TextureKind::UGrooves) expected = -A * std::sqrt(1 - v * v / (R * R));
        }
        ASSERT_NEAR(h, expected, 1e-14) << texture_kind_name(texture) << " point " << i;
      }
    }
}

// Bumps, domes and scales rise from 0 to A; on the cube and the cylinder no
// texture comes within R of an edge, on the saddle none within R of its
// border (in the xy projection).
TEST(SynthesizeShape, FeaturesStayInRangeAndClearOfEdges) {
  const double R = 0.05, A = 0.02;
  for (BaseShape shape : {BaseShape::Cube, BaseShape::Cylinder, BaseShape::Saddle})
    for (TextureKind texture : kTextures) {
      const SynthesizedShape s =
          synthesize_shape(params_for(shape, texture, TextureLayout::Dense, 20000));
      double highest = -1.0, lowest = 1.0;
      for (Eigen::Index i = 0; i < 20000; ++i) {
        const Vector3d b = s.base_positions.row(i);
        double e;
        if (shape == BaseShape::Saddle) {
          e = 0.5 - b.head<2>().norm();
        } else if (shape == BaseShape::Cube) {
          Vector3d a = b.cwiseAbs();
          std::sort(a.data(), a.data() + 3);
          e = 0.5 - a[1];  // the second largest coordinate meets the nearest edge
        } else {
          const bool side = std::abs(b.head<2>().norm() - 0.5) < 1e-12;
          e = side ? 0.5 - std::abs(b.z()) : 0.5 - b.head<2>().norm();
        }
        if (e < R) ASSERT_EQ(s.texture_heights[i], 0.0) << "point " << i << " e " << e;
        highest = std::max(highest, s.texture_heights[i]);
        lowest = std::min(lowest, s.texture_heights[i]);
      }
      const bool grooves = texture == TextureKind::VGrooves || texture == TextureKind::UGrooves;
      const double peak = texture == TextureKind::MultiScale ? A * 4 / 3 : A;
      EXPECT_NEAR(grooves ? -lowest : highest, peak, 0.1 * A) << texture_kind_name(texture);
      EXPECT_EQ(grooves ? highest : lowest, 0.0) << texture_kind_name(texture);
    }
}

TEST(SynthesizeShape, SparseLayoutHasFewerFeaturesThanDense) {
  // Dart throwing with spacing 3R versus 2R: about (3/2)^2 = 2.25 times fewer.
  SynthParams p = params_for(BaseShape::Sphere, TextureKind::Bumps, TextureLayout::Sparse, 10);
  const double sparse = static_cast<double>(synthesize_shape(p).feature_count);
  p.layout = TextureLayout::Dense;
  const double dense = static_cast<double>(synthesize_shape(p).feature_count);
  EXPECT_GT(dense / sparse, 1.8);
  EXPECT_LT(dense / sparse, 2.7);
}

TEST(SynthesizeShape, NoiseMovesPositionsOnly) {
  SynthParams p = params_for(BaseShape::Plane, TextureKind::None, TextureLayout::Sparse, 40000);
  p.noise = 0.001;
  const SynthesizedShape s = synthesize_shape(p);
  EXPECT_DOUBLE_EQ(s.noise_sigma, 0.001 * std::sqrt(2.0));
  double sum_sq = 0.0;
  for (Eigen::Index i = 0; i < 40000; ++i) {
    ASSERT_EQ(s.texture_heights[i], 0.0);
    ASSERT_EQ(s.normals.row(i), Eigen::RowVector3d(0, 0, 1));
    sum_sq += (s.positions.row(i) - s.base_positions.row(i)).squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(sum_sq / (3 * 40000)), s.noise_sigma, 0.02 * s.noise_sigma);
  p.noise = 0.003;
  p.noise_absolute = true;
  EXPECT_DOUBLE_EQ(synthesize_shape(p).noise_sigma, 0.003);
}

TEST(SynthesizeShape, RejectsBadParams) {
  auto rejects = [](auto change, const char* word) {
    SynthParams p;
    change(p);
    try {
      validate_synth_params(p);
      ADD_FAILURE() << "accepted a bad " << word;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  rejects([](SynthParams& p) { p.size = 0.0; }, "size");
  rejects([](SynthParams& p) { p.size = 0.2; }, "size");
  rejects([](SynthParams& p) { p.size = std::nan(""); }, "size");
  rejects([](SynthParams& p) { p.amplitude = 0.06; }, "amplitude");
  rejects([](SynthParams& p) { p.amplitude = -0.06; }, "amplitude");
  rejects([](SynthParams& p) { p.amplitude = std::nan(""); }, "amplitude");
  rejects([](SynthParams& p) { p.points = 0; }, "points");
  rejects([](SynthParams& p) { p.ground_truth_points = -5; }, "ground-truth points");
  rejects([](SynthParams& p) { p.noise = -0.1; }, "noise");
  rejects([](SynthParams& p) { p.noise = 0.5; }, "noise");
  rejects([](SynthParams& p) { p.shape = BaseShape::Mesh; }, "mesh");
  SynthParams ok;
  ok.noise = 0.5;
  ok.noise_absolute = true;
  ok.amplitude = -0.05;
  EXPECT_NO_THROW(validate_synth_params(ok));
  EXPECT_THROW(synthesize_shape(
                   SynthParams{BaseShape::Cube, TextureKind::Bumps, TextureLayout::Sparse, 1.0}),
               std::invalid_argument);
}

TEST(SynthesizeShape, ParsesNames) {
  EXPECT_EQ(parse_base_shape("torus"), BaseShape::Torus);
  EXPECT_EQ(parse_texture_kind("v-grooves"), TextureKind::VGrooves);
  EXPECT_EQ(parse_texture_layout("dense"), TextureLayout::Dense);
  try {
    parse_texture_kind("bump");
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bumps, domes"), std::string::npos) << e.what();
  }
}

int run_cli(const std::string& args, std::string* out);  // below, with the command tests

// Areas against closed forms or independent quadratures.
TEST(SynthesizeShape, NewShapesHaveTheirAreas) {
  auto area_of = [](BaseShape shape) {
    return synthesize_shape(params_for(shape, TextureKind::None, TextureLayout::Sparse, 1)).area;
  };
  {  // Legendre's formula for the triaxial ellipsoid a > b > c.
    const double a = 0.5, b = 0.32, c = 0.2;
    const double phi = std::acos(c / a),
                 k = std::sqrt(a * a * (b * b - c * c) / (b * b * (a * a - c * c)));
    const double expected =
        2 * kPi * c * c + 2 * kPi * a * b / std::sin(phi) *
                              (std::ellint_2(k, phi) * std::pow(std::sin(phi), 2) +
                               std::ellint_1(k, phi) * std::pow(std::cos(phi), 2));
    EXPECT_NEAR(area_of(BaseShape::Ellipsoid), expected, 1e-10 * expected);
  }
  {  // integral over the disk rho <= 0.5 of sqrt(1 + 1.44 rho^2)
    const double expected = 2 * kPi / (3 * 1.44) * (std::pow(1 + 1.44 * 0.25, 1.5) - 1);
    EXPECT_NEAR(area_of(BaseShape::Saddle), expected, 1e-12);
  }
  {  // two sheets of radius 0.37 and a half torus: 2 pi r (pi R0 + 2 r)
    const double expected = 2 * kPi * 0.37 * 0.37 + 2 * kPi * 0.03 * (kPi * 0.37 + 0.06);
    EXPECT_NEAR(area_of(BaseShape::Disc), expected, 1e-12);
  }
  {  // a tube: 2 pi r times the curve's length (a fine polyline)
    double length = 0.0;
    constexpr int n = 200000;
    for (int i = 0; i < n; ++i)
      length += (trefoil(2 * kPi * (i + 1) / n) - trefoil(2 * kPi * i / n)).norm();
    EXPECT_NEAR(area_of(BaseShape::Knot), 2 * kPi * kTube * length, 1e-8);
  }
  {  // blob: midpoint rule in (z, phi) of r sqrt(r^2 + |grad r|^2), gradient by differences
    double total = 0.0;
    constexpr int nz = 1000, nphi = 2000;
    for (int i = 0; i < nz; ++i) {
      const double z = -1 + (i + 0.5) * 2.0 / nz, s = std::sqrt(1 - z * z);
      for (int j = 0; j < nphi; ++j) {
        const double phi = (j + 0.5) * 2 * kPi / nphi;
        const Vector3d d(s * std::cos(phi), s * std::sin(phi), z);
        const Vector3d u = d.unitOrthogonal(), v = d.cross(u);
        const double e = 1e-6, r = blob_radius(d);
        const double ru =
            (blob_radius((d + e * u).normalized()) - blob_radius((d - e * u).normalized())) /
            (2 * e);
        const double rv =
            (blob_radius((d + e * v).normalized()) - blob_radius((d - e * v).normalized())) /
            (2 * e);
        total += r * std::sqrt(r * r + ru * ru + rv * rv);
      }
    }
    total *= (2.0 / nz) * (2 * kPi / nphi);
    EXPECT_NEAR(area_of(BaseShape::Blob), total, 1e-4 * total);
  }
  EXPECT_NEAR(area_of(BaseShape::Mesh), 6.0, 1e-12);
}

// Uniform by area: on a closed surface the mean of b.n over area-uniform
// samples is 3 V / A (divergence theorem), with V known in closed form
// (the blob's from a quadrature of r^3/3); on the saddle, half the area lies
// within the radius where the area formula reaches half its value.
TEST(SynthesizeShape, NewShapesAreSampledUniformlyByArea) {
  constexpr int n = 100000;
  for (BaseShape shape :
       {BaseShape::Ellipsoid, BaseShape::Knot, BaseShape::Blob, BaseShape::Disc}) {
    SynthParams p = params_for(shape, TextureKind::None, TextureLayout::Sparse, n);
    const SynthesizedShape s = synthesize_shape(p);
    double volume = 0.0;
    if (shape == BaseShape::Ellipsoid) volume = 4.0 / 3.0 * kPi * 0.5 * 0.32 * 0.2;
    if (shape == BaseShape::Knot) volume = kPi * kTube * kTube * s.area / (2 * kPi * kTube);
    if (shape == BaseShape::Disc)  // Pappus for the rim's half disc (centroid 4r/(3 pi) out)
      volume = kPi * 0.37 * 0.37 * 0.06 + kPi * 0.03 * 0.03 / 2 * 2 * kPi * (0.37 + 0.04 / kPi);
    if (shape == BaseShape::Blob) {
      constexpr int nz = 1000, nphi = 2000;
      for (int i = 0; i < nz; ++i) {
        const double z = -1 + (i + 0.5) * 2.0 / nz, r = std::sqrt(1 - z * z);
        for (int j = 0; j < nphi; ++j) {
          const double phi = (j + 0.5) * 2 * kPi / nphi;
          volume += std::pow(blob_radius(Vector3d(r * std::cos(phi), r * std::sin(phi), z)), 3) / 3;
        }
      }
      volume *= (2.0 / nz) * (2 * kPi / nphi);
    }
    double sum = 0.0, sum_sq = 0.0;
    for (int i = 0; i < n; ++i) {
      const double v = s.ground_truth_positions.row(i).dot(s.ground_truth_normals.row(i));
      sum += v;
      sum_sq += v * v;
    }
    const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
    EXPECT_NEAR(mean, 3 * volume / s.area, 5 * sd / std::sqrt(n) + 1e-4 * mean)
        << base_shape_name(shape);
  }
  {
    const SynthesizedShape s = synthesize_shape(
        params_for(BaseShape::Saddle, TextureKind::None, TextureLayout::Sparse, n));
    // (1 + 1.44 rho^2)^1.5 - 1 reaches half of its value at rho = 0.5.
    const double half =
        std::sqrt((std::pow(0.5 * (std::pow(1.36, 1.5) - 1) + 1, 2.0 / 3) - 1) / 1.44);
    int inside = 0;
    for (int i = 0; i < n; ++i) inside += s.ground_truth_positions.row(i).head<2>().norm() < half;
    EXPECT_NEAR(inside, n / 2, 5 * std::sqrt(n / 4.0));
  }
  {
    const SynthesizedShape s =
        synthesize_shape(params_for(BaseShape::Mesh, TextureKind::None, TextureLayout::Sparse, n));
    int per_face[6] = {0, 0, 0, 0, 0, 0};
    for (int i = 0; i < n; ++i) {
      int a = 0;
      s.ground_truth_normals.row(i).cwiseAbs().maxCoeff(&a);
      ++per_face[2 * a + (s.ground_truth_normals(i, a) > 0)];
    }
    for (int f = 0; f < 6; ++f) EXPECT_NEAR(per_face[f], n / 6.0, 5 * std::sqrt(n / 6.0)) << f;
  }
}

// The knot's strands pass close, but its tube never meets itself: every
// pair of curve points more than 0.6 apart along the curve is farther apart
// than 2 r + 0.05.
TEST(SynthesizeShape, KnotStrandsKeepTheirGap) {
  constexpr int n = 3000;
  std::vector<Vector3d> c(n);
  std::vector<double> arc(n + 1, 0.0);
  for (int i = 0; i < n; ++i) c[i] = trefoil(2 * kPi * i / n);
  for (int i = 0; i < n; ++i) arc[i + 1] = arc[i] + (c[(i + 1) % n] - c[i]).norm();
  double closest = 1e300;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const double along = std::min(arc[j] - arc[i], arc[n] - (arc[j] - arc[i]));
      if (along > 0.6) closest = std::min(closest, (c[i] - c[j]).norm());
    }
  EXPECT_GT(closest - 2 * kTube, 0.05);
  EXPECT_LT(closest - 2 * kTube, 0.08) << "the strands do pass close";
}

// On the disc a bump centered on the top sheet must not lift the bottom
// sheet 0.06 below it: on the flat sheets, h is the sum of the bumps whose
// center normal agrees with the point's (weight 1 at n.n_c >= 1/2, 0 at
// n.n_c <= 0).
TEST(SynthesizeShape, DiscFeaturesStayOnTheirSide) {
  const double R = 0.1, A = 0.05;
  SynthParams p = params_for(BaseShape::Disc, TextureKind::Bumps, TextureLayout::Dense, 20000);
  p.size = R;
  p.amplitude = A;
  const SynthesizedShape s = synthesize_shape(p);
  ASSERT_GT(s.feature_count, 10u);
  int checked = 0, under_other_side = 0;
  for (Eigen::Index i = 0; i < s.base_positions.rows(); ++i) {
    const Vector3d b = s.base_positions.row(i), n = s.base_normals.row(i);
    if (on_disc_rim(b)) continue;
    double expected = 0.0;
    bool exact = true, near_other = false;
    for (Eigen::Index j = 0; j < s.feature_centers.rows(); ++j) {
      const Vector3d c = s.feature_centers.row(j), nc = s.feature_normals.row(j);
      const double q = n.dot(nc), d_sq = (b - c).squaredNorm() / (R * R);
      if (d_sq >= 1) continue;
      if (q <= 0) {
        near_other = true;
        continue;
      }
      if (q < 0.5) exact = false;  // a rim center in the fade: not checked
      expected += A * std::exp(-2 * d_sq) * (1 - d_sq) * (1 - d_sq);
    }
    if (!exact) continue;
    ++checked;
    under_other_side += near_other;
    ASSERT_NEAR(s.texture_heights[i], expected, 1e-15) << "point " << i;
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(under_other_side, 1000) << "points within R of a center on the other sheet";
}

// A base mesh from PLY faces: triangles and quads (fan-triangulated) give the
// same cube; a degenerate triangle is skipped; samples lie on the faces.
TEST(SynthesizeShape, MeshBaseFromPlyFaces) {
  const auto dir = std::filesystem::temp_directory_path() / "detexture_test_synth_mesh";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "cube_quads.ply").string();
  {
    std::ofstream f(path);
    f << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
         "property float z\nelement face 7\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 8; ++i)
      f << (i & 1 ? 0.5 : -0.5) << " " << (i & 2 ? 0.5 : -0.5) << " " << (i & 4 ? 0.5 : -0.5)
        << "\n";
    f << "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n3 0 0 1\n";
  }
  const BaseMesh mesh = base_mesh_from_cloud(read_point_cloud(path));
  EXPECT_EQ(mesh.triangles.rows(), 13);
  SynthParams p = params_for(BaseShape::Mesh, TextureKind::Bumps, TextureLayout::Sparse, 5000);
  p.mesh = std::make_shared<const BaseMesh>(mesh);
  const SynthesizedShape s = synthesize_shape(p);
  EXPECT_NEAR(s.area, 6.0, 1e-12);
  EXPECT_NEAR(s.diagonal, std::sqrt(3.0), 1e-12);
  EXPECT_EQ(s.degenerate_triangles, 1u);
  for (Eigen::Index i = 0; i < 5000; ++i) {
    const Vector3d b = s.base_positions.row(i);
    ASSERT_LT(distance_to_base(BaseShape::Cube, b), 1e-12);
    ASSERT_LT((s.base_normals.row(i).transpose() - base_normal(BaseShape::Cube, b)).norm(), 1e-15);
  }
  std::string text;
  ASSERT_EQ(run_cli("synth --base-mesh " + path + " --points 500 --ground-truth-points 500 -o " +
                        (dir / "m.ply").string(),
                    &text),
            0)
      << text;
  EXPECT_NE(text.find("base area 6 diagonal 1.73205\n"), std::string::npos) << text;
  EXPECT_NE(text.find("skipped 1 degenerate triangles"), std::string::npos) << text;
  EXPECT_EQ(run_cli("synth --base-mesh " + (dir / "missing.ply").string() + " -o " +
                        (dir / "m.ply").string(),
                    &text),
            3)
      << text;
  EXPECT_EQ(
      run_cli("synth --base-mesh " + path + " --shape cube -o " + (dir / "m.ply").string(), &text),
      2)
      << text;
  std::filesystem::remove_all(dir);
  PointCloud no_faces;
  no_faces.positions = mesh.vertices;
  EXPECT_THROW(base_mesh_from_cloud(no_faces), std::invalid_argument);
}

// An open mesh: the square [-0.5, 0.5]^2 as two triangles has the plane
// patch's border, so line textures on it equal those on the plane shape at
// the same points, and no texture comes within R of the boundary.
TEST(SynthesizeShape, OpenMeshKeepsTextureOffItsBoundary) {
  auto square = std::make_shared<BaseMesh>();
  square->vertices.resize(4, 3);
  square->vertices << -0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0;
  square->triangles.resize(2, 3);
  square->triangles << 0, 1, 2, 0, 2, 3;
  for (TextureKind texture :
       {TextureKind::Waves, TextureKind::UGrooves, TextureKind::Bumps, TextureKind::Scales}) {
    SynthParams p = params_for(BaseShape::Mesh, texture, TextureLayout::Dense, 20000);
    p.mesh = square;
    const SynthesizedShape s = synthesize_shape(p);
    EXPECT_NEAR(s.area, 1.0, 1e-15);
    SynthParams plane = params_for(BaseShape::Plane, texture, TextureLayout::Dense, 1);
    const TexturedSamples t = evaluate_texture(plane, s.base_positions);
    std::size_t textured = 0;
    for (Eigen::Index i = 0; i < 20000; ++i) {
      const Vector3d b = s.base_positions.row(i);
      const double e = 0.5 - std::max(std::abs(b.x()), std::abs(b.y()));
      if (e < 0.05) ASSERT_EQ(s.texture_heights[i], 0.0) << texture_kind_name(texture) << " " << i;
      textured += s.is_texture[i];
      if (texture == TextureKind::Waves || texture == TextureKind::UGrooves)
        ASSERT_NEAR(s.texture_heights[i], t.heights[i], 1e-14) << texture_kind_name(texture);
    }
    EXPECT_GT(textured, 5000u) << texture_kind_name(texture);
  }
}

// The command line writes both files with the extra properties.
int run_cli(const std::string& args, std::string* out = nullptr) {
  const std::string command = std::string(DETEXTURE_CLI_PATH) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  char buf[512];
  std::string text;
  while (std::fgets(buf, sizeof buf, pipe)) text += buf;
  const int status = pclose(pipe);
  if (out) *out = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SynthCommand, WritesCloudAndGroundTruth) {
  const auto dir = std::filesystem::temp_directory_path() / "detexture_test_synth";
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "cube.ply").string();
  std::string text;
  ASSERT_EQ(run_cli("synth --shape cube --texture domes --points 2000 --ground-truth-points 3000 "
                    "--seed 4 -o " +
                        out,
                    &text),
            0)
      << text;
  EXPECT_NE(text.find((dir / "cube.gt.ply").string()), std::string::npos) << text;
  const PointCloud cloud = read_point_cloud(out);
  const PointCloud truth = read_point_cloud((dir / "cube.gt.ply").string());
  ASSERT_EQ(cloud.size(), 2000u);
  ASSERT_EQ(truth.size(), 3000u);
  EXPECT_TRUE(cloud.has_normals());
  EXPECT_TRUE(truth.has_normals());
  SynthParams p = params_for(BaseShape::Cube, TextureKind::Domes, TextureLayout::Sparse, 2000);
  p.ground_truth_points = 3000;
  p.seed = 4;
  const SynthesizedShape s = synthesize_shape(p);
  EXPECT_EQ(cloud.positions, s.positions);
  ASSERT_EQ(cloud.extras.size(), 2u);
  EXPECT_EQ(cloud.extras[0].name, "texture_height");
  EXPECT_EQ(cloud.extras[0].values, s.texture_heights);
  EXPECT_EQ(cloud.extras[1].name, "is_texture");
  EXPECT_EQ(cloud.extras[1].values, std::vector<double>(s.is_texture.begin(), s.is_texture.end()));
  std::filesystem::remove_all(dir);
}

TEST(SynthCommand, BadValuesAreUsageErrors) {
  std::string text;
  EXPECT_EQ(run_cli("synth --shape cube --size 0.5 -o /tmp/x.ply", &text), 2);
  EXPECT_NE(text.find("feature size"), std::string::npos) << text;
  EXPECT_EQ(run_cli("synth --shape blobby -o /tmp/x.ply", &text), 2);
  EXPECT_EQ(run_cli("synth --shape mesh -o /tmp/x.ply", &text), 2) << "mesh without --base-mesh";
  EXPECT_NE(text.find("--base-mesh"), std::string::npos) << text;
  EXPECT_EQ(run_cli("synth --shape cube", &text), 2) << "missing -o";
  EXPECT_EQ(run_cli("synth --help", &text), 0);
  EXPECT_NE(text.find("--amplitude FLOAT=0.02"), std::string::npos) << text;
}

}  // namespace
}  // namespace detexture
