#include "detexture/eval/compare_to_ground_truth.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "detexture/io/write_point_cloud.h"

namespace detexture {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The plane z = 0 sampled on a grid of spacing 0.01 over [-1, 1]^2.
void grid_plane(Positions& G, Normals& GN) {
  const int n = 201;
  G.resize(n * n, 3);
  GN.resize(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      G.row(i * n + j) << (i - 100) * 0.01, (j - 100) * 0.01, 0.0;
      GN.row(i * n + j) << 0.0, 0.0, 1.0;
    }
}

// Above the plane z = 0, point-to-plane distances are the heights:
// heights 0.1, -0.2, 0.3, 0 give Dmax 0.3, Dmean 0.15,
// sigma^2 = (0.05^2 + 0.05^2 + 0.15^2 + 0.15^2)/4 = 0.0125, signed mean 0.05,
// signed variance (0.05^2 + 0.25^2 + 0.25^2 + 0.05^2)/4 = 0.0325.
TEST(CompareToGroundTruth, PlaneDistancesByHand) {
  Positions G;
  Normals GN;
  grid_plane(G, GN);
  Positions R(4, 3);
  R << 0.1234, 0.2, 0.1, -0.3, 0.4567, -0.2, 0.5, -0.5, 0.3, 0.0, 0.0, 0.0;
  const GroundTruthComparison c = compare_to_ground_truth(R, Normals(), G, GN);
  EXPECT_EQ(c.result_points, 4u);
  EXPECT_EQ(c.ground_truth_points, 201u * 201u);
  EXPECT_NEAR(c.diagonal, 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(c.max_distance, 0.3, 1e-15);
  EXPECT_NEAR(c.mean_distance, 0.15, 1e-15);
  EXPECT_NEAR(c.std_distance, std::sqrt(0.0125), 1e-15);
  EXPECT_NEAR(c.mean_signed_distance, 0.05, 1e-15);
  EXPECT_NEAR(c.std_signed_distance, std::sqrt(0.0325), 1e-15);
  EXPECT_FALSE(c.has_normals);
}

// Normals at 0, 5, 20 and 90 degrees from +z, one flipped (180 degrees: the
// angle is oriented) and one zero (left out): mean (0+5+20+90+180)/5 = 59,
// two of five within 10 degrees.
TEST(CompareToGroundTruth, NormalAnglesByHand) {
  Positions G;
  Normals GN;
  grid_plane(G, GN);
  const double degrees[] = {0.0, 5.0, 20.0, 90.0, 180.0};
  Positions R = Positions::Zero(6, 3);
  Normals RN = Normals::Zero(6, 3);
  for (int i = 0; i < 5; ++i) {
    const double a = degrees[i] * kPi / 180.0;
    RN.row(i) << std::sin(a), 0.0, std::cos(a);
  }
  const GroundTruthComparison c = compare_to_ground_truth(R, RN, G, GN);
  EXPECT_TRUE(c.has_normals);
  EXPECT_EQ(c.zero_normals, 1u);
  EXPECT_NEAR(c.mean_angle_degrees, 59.0, 1e-12);
  EXPECT_NEAR(c.within_10_degrees_percent, 40.0, 1e-12);
}

// On the unit sphere, points at radius 1.05 and 0.95 are 0.05 from the
// surface, up to the point-to-plane error 1.05 (1 - cos a) at the nearest of
// 200000 samples (a < 0.01 rad: < 5.3e-5).
TEST(CompareToGroundTruth, SphereDistanceIsRadiusDifference) {
  const int n = 200000, m = 2000;
  Positions G(n, 3), R(m, 3);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z);
    G.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  for (int i = 0; i < m; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / m, r = std::sqrt(1.0 - z * z);
    R.row(i) << r * std::cos(2.4 * i), r * std::sin(2.4 * i), z;
    R.row(i) *= (i % 2 == 0) ? 1.05 : 0.95;
  }
  const GroundTruthComparison c = compare_to_ground_truth(R, Normals(), G, G);
  EXPECT_NEAR(c.mean_distance, 0.05, 6e-5);
  EXPECT_NEAR(c.max_distance, 0.05, 6e-5);
  EXPECT_LT(c.std_distance, 6e-5);
  EXPECT_NEAR(c.mean_signed_distance, 0.0, 6e-5);
  EXPECT_NEAR(c.std_signed_distance, 0.05, 6e-5);
}

// Coverage: the grid shifted by 0.01 along z covers every sample at 0.01;
// keeping only the half x < 0 leaves the column x = 1 at 1.01 from the rest.
TEST(CompareToGroundTruth, CoverageShowsShiftsAndHoles) {
  Positions G;
  Normals GN;
  grid_plane(G, GN);
  Positions shifted = G;
  shifted.col(2).array() += 0.01;
  GroundTruthComparison c = compare_to_ground_truth(shifted, Normals(), G, GN);
  EXPECT_NEAR(c.mean_coverage_distance, 0.01, 1e-15);
  EXPECT_NEAR(c.max_coverage_distance, 0.01, 1e-15);
  EXPECT_NEAR(c.mean_signed_distance, 0.01, 1e-15);
  EXPECT_NEAR(c.std_signed_distance, 0.0, 1e-15);

  Positions half(100 * 201, 3);
  for (int i = 0; i < 100 * 201; ++i) half.row(i) = G.row(i);  // rows with x = -1 .. -0.01
  c = compare_to_ground_truth(half, Normals(), G, GN);
  EXPECT_NEAR(c.max_coverage_distance, 1.01, 1e-12);
  EXPECT_EQ(c.max_distance, 0.0);
}

TEST(CompareToGroundTruth, RejectsInconsistentInputs) {
  Positions G;
  Normals GN;
  grid_plane(G, GN);
  const Positions R = Positions::Zero(3, 3);
  EXPECT_THROW(compare_to_ground_truth(Positions(), Normals(), G, GN), std::invalid_argument);
  EXPECT_THROW(compare_to_ground_truth(R, Normals(), Positions(), Normals()),
               std::invalid_argument);
  EXPECT_THROW(compare_to_ground_truth(R, Normals(), G, Normals()), std::invalid_argument);
  EXPECT_THROW(compare_to_ground_truth(R, Normals::Zero(2, 3), G, GN), std::invalid_argument);
}

const char* kJsonKeys[] = {"result_points",
                           "ground_truth_points",
                           "diagonal",
                           "dmax",
                           "dmean",
                           "dstd",
                           "dmax_relative",
                           "dmean_relative",
                           "dstd_relative",
                           "signed_mean",
                           "signed_std",
                           "signed_mean_relative",
                           "signed_std_relative",
                           "normal_angle_mean_degrees",
                           "normals_within_10_degrees_percent",
                           "zero_normals",
                           "coverage_mean",
                           "coverage_max",
                           "coverage_mean_relative",
                           "coverage_max_relative"};

TEST(CompareToGroundTruth, JsonHasStableKeys) {
  GroundTruthComparison c;
  c.diagonal = 2.0;
  c.max_distance = 0.5;
  const std::string json = comparison_to_json(c);
  for (const char* key : kJsonKeys)
    EXPECT_NE(json.find("\"" + std::string(key) + "\": "), std::string::npos) << key;
  EXPECT_NE(json.find("\"dmax_relative\": 0.25,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"normal_angle_mean_degrees\": null"), std::string::npos) << json;
  c.has_normals = true;
  c.mean_angle_degrees = 3.5;
  EXPECT_NE(comparison_to_json(c).find("\"normal_angle_mean_degrees\": 3.5,"), std::string::npos);
  EXPECT_NE(comparison_to_table(c).find("Dmax"), std::string::npos);
}

int run_cli(const std::string& args, std::string* out) {
  const std::string command = std::string(DETEXTURE_CLI_PATH) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return -1;
  char buf[512];
  out->clear();
  while (std::fgets(buf, sizeof buf, pipe)) *out += buf;
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(CompareCommand, PrintsJsonForFiles) {
  const auto dir = std::filesystem::temp_directory_path() / "detexture_test_compare";
  std::filesystem::create_directories(dir);
  PointCloud truth, result;
  grid_plane(truth.positions, truth.normals);
  result.positions.resize(2, 3);
  result.positions << 0.1, 0.1, 0.25, -0.1, 0.3, -0.25;
  write_point_cloud((dir / "truth.ply").string(), truth);
  write_point_cloud((dir / "result.ply").string(), result);
  std::string text;
  ASSERT_EQ(run_cli("compare --json " + (dir / "result.ply").string() + " " +
                        (dir / "truth.ply").string(),
                    &text),
            0)
      << text;
  for (const char* key : kJsonKeys) EXPECT_NE(text.find(key), std::string::npos) << key;
  EXPECT_NE(text.find("\"dmean\": 0.25,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"signed_mean\": 0,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"normal_angle_mean_degrees\": null"), std::string::npos) << text;

  ASSERT_EQ(run_cli("compare " + (dir / "result.ply").string() + " " + (dir / "truth.ply").string(),
                    &text),
            0);
  EXPECT_NE(text.find("n/a"), std::string::npos) << text;

  // Ground truth without normals, and a missing file: input errors.
  EXPECT_EQ(run_cli("compare " + (dir / "truth.ply").string() + " " + (dir / "result.ply").string(),
                    &text),
            3);
  EXPECT_NE(text.find("no normals"), std::string::npos) << text;
  EXPECT_EQ(
      run_cli("compare " + (dir / "missing.ply").string() + " " + (dir / "truth.ply").string(),
              &text),
      3);
  EXPECT_EQ(run_cli("compare " + (dir / "result.ply").string(), &text), 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace detexture
