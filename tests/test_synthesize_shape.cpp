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
#include <string>

#include "detexture/io/read_point_cloud.h"

namespace detexture {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
const BaseShape kShapes[] = {BaseShape::Sphere, BaseShape::Cube,    BaseShape::Cylinder,
                             BaseShape::Torus,  BaseShape::Pyramid, BaseShape::Plane};
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

// Distance from x to the analytic base surface, for points on or near it.
double distance_to_base(BaseShape shape, const Vector3d& x) {
  switch (shape) {
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
  }
  return 1e300;
}

// Outward normal of the base at a point b on it, and the projection of a
// nearby point onto the same smooth piece as b.
Vector3d base_normal(BaseShape shape, const Vector3d& b) {
  switch (shape) {
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
}

TEST(SynthesizeShape, BaseAndGroundTruthLieOnTheAnalyticShape) {
  for (BaseShape shape : kShapes) {
    const SynthesizedShape s =
        synthesize_shape(params_for(shape, TextureKind::Bumps, TextureLayout::Dense, 4000));
    ASSERT_EQ(s.base_positions.rows(), 4000);
    ASSERT_EQ(s.ground_truth_positions.rows(), 4000);
    for (Eigen::Index i = 0; i < 4000; ++i) {
      const Vector3d b = s.base_positions.row(i).transpose();
      ASSERT_LT(distance_to_base(shape, b), 1e-12) << base_shape_name(shape) << " base " << i;
      ASSERT_LT((s.base_normals.row(i).transpose() - base_normal(shape, b)).norm(), 1e-12);
      const Vector3d g = s.ground_truth_positions.row(i).transpose();
      ASSERT_LT(distance_to_base(shape, g), 1e-12) << base_shape_name(shape) << " truth " << i;
      ASSERT_LT((s.ground_truth_normals.row(i).transpose() - base_normal(shape, g)).norm(), 1e-12);
    }
  }
}

TEST(SynthesizeShape, DisplacementIsHeightAlongBaseNormal) {
  for (BaseShape shape : kShapes)
    for (TextureKind texture : kTextures) {
      const SynthesizedShape s =
          synthesize_shape(params_for(shape, texture, TextureLayout::Sparse, 3000));
      std::size_t textured = 0;
      for (Eigen::Index i = 0; i < 3000; ++i) {
        const double h = s.texture_heights[i];
        const Vector3d p = s.positions.row(i), b = s.base_positions.row(i),
                       n = s.base_normals.row(i);
        ASSERT_LT((p - (b + h * n)).norm(), 1e-15);
        ASSERT_EQ(s.is_texture[i], std::abs(h) > kTextureHeightEpsilon ? 1 : 0);
        // Multi-scale heights add: A + A/3 at most.
        const double peak = texture == TextureKind::MultiScale ? 0.02 * 4 / 3 : 0.02;
        ASSERT_LE(std::abs(h), peak + 1e-15) << "|h| <= A";
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
TEST(SynthesizeShape, NormalsMatchFiniteDifferences) {
  constexpr double step = 1e-7;
  for (BaseShape shape : kShapes)
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
// texture comes within R of an edge.
TEST(SynthesizeShape, FeaturesStayInRangeAndClearOfEdges) {
  const double R = 0.05, A = 0.02;
  for (BaseShape shape : {BaseShape::Cube, BaseShape::Cylinder})
    for (TextureKind texture : kTextures) {
      const SynthesizedShape s =
          synthesize_shape(params_for(shape, texture, TextureLayout::Dense, 20000));
      double highest = -1.0, lowest = 1.0;
      for (Eigen::Index i = 0; i < 20000; ++i) {
        const Vector3d b = s.base_positions.row(i);
        double e;
        if (shape == BaseShape::Cube) {
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
  EXPECT_EQ(run_cli("synth --shape blob -o /tmp/x.ply", &text), 2);
  EXPECT_EQ(run_cli("synth --shape cube", &text), 2) << "missing -o";
  EXPECT_EQ(run_cli("synth --help", &text), 0);
  EXPECT_NE(text.find("--amplitude FLOAT=0.02"), std::string::npos) << text;
}

}  // namespace
}  // namespace detexture
