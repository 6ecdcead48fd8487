// Reading and writing files made to hurt: mixed precisions, huge headers,
// endless devices, odd line endings, extreme coordinates. Every case here
// lost data, hung or gave a wrong answer before (issue 11).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;

class HostileInput : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device device;
    dir_ = fs::temp_directory_path() /
           ("detexture_hostile_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(device()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  static std::string read_error(const std::string& p, FileFormat format = FileFormat::Auto) {
    try {
      read_point_cloud(p, format);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// float x but double y z: y = 1e300 does not fit a float. All three are
// written as double, and read back exactly.
TEST_F(HostileInput, MixedPrecisionPositionsKeepTheWidestType) {
  const std::string in = write("mixed.ply",
                               "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                               "property double y\nproperty double z\n"
                               "property float nx\nproperty float ny\nproperty double nz\n"
                               "end_header\n"
                               "0.5 1e300 0.1 0 0 1\n1 -2.000000000000001 3 1 0 0\n");
  const PointCloud cloud = read_point_cloud(in);
  EXPECT_EQ(cloud.position_type, ScalarType::Float64);
  EXPECT_EQ(cloud.normal_type, ScalarType::Float64);
  write_point_cloud(path("out.ply"), cloud);
  const PointCloud back = read_point_cloud(path("out.ply"));
  EXPECT_EQ(back.positions, cloud.positions);
  EXPECT_EQ(back.positions(0, 1), 1e300);
  EXPECT_EQ(back.positions(1, 1), -2.000000000000001);
  EXPECT_EQ(back.positions(0, 2), 0.1) << "double detail in z is kept";
}

// A float cloud whose values no longer fit a float (moved by a filter) is
// written as double rather than as inf.
TEST_F(HostileInput, FloatCloudWithValuesBeyondFloatIsWrittenAsDouble) {
  PointCloud cloud;
  cloud.positions.resize(2, 3);
  cloud.positions << 0, 0, 0, 1, 1e39, 2;
  cloud.position_type = ScalarType::Float32;
  write_point_cloud(path("big.ply"), cloud);
  const PointCloud back = read_point_cloud(path("big.ply"));
  EXPECT_EQ(back.positions(1, 1), 1e39);
  EXPECT_EQ(back.position_type, ScalarType::Float64);
}

}  // namespace
}  // namespace detexture

namespace detexture {
namespace {

// 200k properties: the duplicate-name check scanned the earlier properties
// for each one (O(N²): 80k took 12 s). Now linear.
TEST_F(HostileInput, HeaderWithManyPropertiesParsesInLinearTime) {
  const int properties = 200000;
  std::string text = "ply\nformat ascii 1.0\nelement vertex 1\n";
  text += "property float x\nproperty float y\nproperty float z\n";
  for (int k = 0; k < properties; ++k) text += "property uchar p" + std::to_string(k) + "\n";
  text += "end_header\n1 2 3";
  for (int k = 0; k < properties; ++k) text += " 7";
  text += "\n";
  const std::string in = write("wide.ply", text);
  const auto t0 = std::chrono::steady_clock::now();
  const PointCloud cloud = read_point_cloud(in);
  EXPECT_LT(seconds_since(t0), 2.0);
  ASSERT_EQ(cloud.extras.size(), std::size_t(properties));
  EXPECT_EQ(cloud.extras.back().name, "p199999");
  EXPECT_EQ(cloud.extras.back().values[0], 7.0);
  const auto t1 = std::chrono::steady_clock::now();
  write_point_cloud(path("wide.out.ply"), cloud);
  EXPECT_LT(seconds_since(t1), 2.0) << "the writer's name check is linear too";
}

// /dev/zero never ends: it fails on its first bytes, naming the file.
TEST_F(HostileInput, DevZeroFailsAtOnceAsPlyAndAsXyz) {
  if (!fs::exists("/dev/zero")) GTEST_SKIP() << "no /dev/zero";
  for (const FileFormat format : {FileFormat::Ply, FileFormat::Xyz}) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string error = read_error("/dev/zero", format);
    EXPECT_LT(seconds_since(t0), 2.0);
    EXPECT_NE(error.find("'/dev/zero'"), std::string::npos) << error;
    EXPECT_NE(error.find(format == FileFormat::Ply ? "not a PLY file" : "NUL byte"),
              std::string::npos)
        << error;
  }
}

// One 50 MB line used to become one point with 25M extra columns (3.3 GB).
TEST_F(HostileInput, HugeXyzLineIsRefusedWithItsBound) {
  std::string line = "1 2 3";
  line.reserve(50u << 20);
  while (line.size() < (50u << 20)) line += " 0";
  const std::string in = write("long.xyz", line + "\n");
  const std::string error = read_error(in);
  EXPECT_NE(error.find("long.xyz"), std::string::npos) << error;
  EXPECT_NE(error.find("line 1"), std::string::npos) << error;
  EXPECT_NE(error.find("more than 1 MiB"), std::string::npos) << error;
}

TEST_F(HostileInput, XyzColumnsAreBounded) {
  std::string row = "1 2 3 0 0 1";
  for (std::size_t c = 6; c < kMaxXyzColumns + 1; ++c) row += " 5";
  const std::string error = read_error(write("wide.xyz", row + "\n"));
  EXPECT_NE(error.find("1025 values, more than the 1024 columns"), std::string::npos) << error;
  row = "1 2 3 0 0 1";
  for (std::size_t c = 6; c < kMaxXyzColumns; ++c) row += " 5";
  EXPECT_EQ(read_point_cloud(write("ok.xyz", row + "\n")).extras.size(), kMaxXyzColumns - 6);
}

// A header that never ends is refused once it passes its bound.
TEST_F(HostileInput, EndlessPlyHeaderIsRefusedWithItsBound) {
  std::string text = "ply\nformat ascii 1.0\n";
  const std::string comment = "comment " + std::string(120, 'x') + "\n";
  while (text.size() <= kMaxPlyHeaderBytes) text += comment;
  const std::string error = read_error(write("endless.ply", text));
  EXPECT_NE(error.find("endless.ply"), std::string::npos) << error;
  EXPECT_NE(error.find("longer than 64 MiB"), std::string::npos) << error;
}

// Old Mac files end lines with a lone CR: they read as one point before.
TEST_F(HostileInput, XyzLineEndingsCrCrlfAndLfReadTheSame) {
  for (const std::string& eol : {std::string("\n"), std::string("\r\n"), std::string("\r")}) {
    const std::string in =
        write("eol.xyz", "# header" + eol + "0 0 0" + eol + "1 2 3" + eol + eol + "4 5 6" + eol);
    const PointCloud cloud = read_point_cloud(in);
    ASSERT_EQ(cloud.size(), 3u) << "line ending of " << eol.size() << " bytes";
    EXPECT_EQ(cloud.positions(2, 2), 6.0);
  }
  const PointCloud mixed = read_point_cloud(write("mixed.xyz", "0 0 0\r1 1 1\r\n2 2 2\n3 3 3"));
  ASSERT_EQ(mixed.size(), 4u);
  EXPECT_EQ(mixed.positions(3, 0), 3.0);
  // An ascii PLY with CR line ends reads too.
  const PointCloud ply = read_point_cloud(
      write("cr.ply",
            "ply\rformat ascii 1.0\relement vertex 2\rproperty float x\rproperty float y\r"
            "property float z\rend_header\r1 2 3\r4 5 6\r"));
  ASSERT_EQ(ply.size(), 2u);
  EXPECT_EQ(ply.positions(1, 2), 6.0);
}

// Old Blender writes a bare "Created by ..." line. Before the first element
// an unknown line cannot change how the data is read: kept as a comment,
// with a notice. After it, it could be a misspelled property: refused.
TEST_F(HostileInput, UnknownHeaderLineBeforeTheElementsIsKeptAsAComment) {
  const std::string body =
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n1 2 3\n";
  const std::string in = write(
      "blender.ply",
      "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n" + body);
  ReadReport report;
  const PointCloud cloud = read_point_cloud(in, FileFormat::Auto, &report);
  ASSERT_EQ(cloud.size(), 1u);
  ASSERT_EQ(cloud.comments.size(), 1u);
  EXPECT_EQ(cloud.comments[0], "Created by Blender3D 247 - www.blender.org, source file: ");
  ASSERT_EQ(report.notices.size(), 1u);
  EXPECT_NE(report.notices[0].find("line 3"), std::string::npos) << report.notices[0];
  const std::string late = write("late.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                 "propety float y\nproperty float z\nend_header\n1 2 3\n");
  EXPECT_NE(read_error(late).find("line 5: unknown header keyword 'propety'"), std::string::npos)
      << read_error(late);
}

}  // namespace
}  // namespace detexture

namespace detexture {
namespace {

// Found by fuzz/fuzz_read_ply: a name with a control character (0x7f) was
// read, and then the writer refused the cloud.
TEST_F(HostileInput, NamesWithControlCharactersAreRefused) {
  const std::string in = write("ctrl.ply",
                               "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                               "property float y\nproperty float z\nproperty int \x7fl\n"
                               "end_header\n1 2 3 4\n");
  EXPECT_NE(read_error(in).find("line 7: the name"), std::string::npos) << read_error(in);
  EXPECT_NE(read_error(in).find("contains a control character"), std::string::npos);
}

}  // namespace
}  // namespace detexture
