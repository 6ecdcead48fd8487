// Our PCD files against the Point Cloud Library's own tools (Debian's
// pcl-tools, installed by scripts/install_peer_deps.sh): what we write, PCL
// reads (pcl_pcd2ply), and what PCL writes, we read (pcl_ply2pcd). Skipped
// when the tools are missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;

bool have_tool(const char* name) {
  return std::system(("command -v " + std::string(name) + " >/dev/null 2>&1").c_str()) == 0;
}

class PclTools : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_tool("pcl_pcd2ply") || !have_tool("pcl_ply2pcd"))
      GTEST_SKIP() << "pcl_pcd2ply / pcl_ply2pcd not installed (Debian pcl-tools)";
    std::random_device device;
    dir_ = fs::temp_directory_path() / ("detexture_pcl_" + std::to_string(device()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  int run(const std::string& command) const {
    return std::system((command + " >" + path("log.txt") + " 2>&1").c_str());
  }

  // 200 points with float positions and normals, colours and an intensity.
  static PointCloud cloud() {
    PointCloud c;
    const int n = 200;
    c.positions.resize(n, 3);
    c.normals.resize(n, 3);
    c.position_type = c.normal_type = ScalarType::Float32;
    PointProperty red{"red", ScalarType::UInt8, {}}, green{"green", ScalarType::UInt8, {}},
        blue{"blue", ScalarType::UInt8, {}}, intensity{"intensity", ScalarType::Float32, {}};
    for (int i = 0; i < n; ++i) {
      c.positions.row(i) << static_cast<float>(i * 0.01), static_cast<float>(1.0 / (i + 1)),
          static_cast<float>(-0.5 * i);
      c.normals.row(i) << (i % 3 == 0), (i % 3 == 1), (i % 3 == 2);
      red.values.push_back(i % 256);
      green.values.push_back((7 * i) % 256);
      blue.values.push_back(255 - i % 256);
      intensity.values.push_back(static_cast<float>(i * 0.25));
    }
    c.positions = c.positions.cast<float>().cast<double>();
    c.extras = {red, green, blue, intensity};
    return c;
  }

  fs::path dir_;
};

const PointProperty* extra(const PointCloud& c, const std::string& name) {
  for (const PointProperty& p : c.extras)
    if (p.name == name) return &p;
  return nullptr;
}

// tolerance 0: bit for bit; PCL's ascii PCD writer prints 8 significant
// digits, one short of what every float needs to read back exactly.
void expect_same_points(const PointCloud& a, const PointCloud& b, const std::string& what,
                        double tolerance = 0.0) {
  ASSERT_EQ(a.size(), b.size()) << what;
  if (tolerance == 0.0)
    EXPECT_EQ(a.positions, b.positions) << what;
  else
    EXPECT_LE((a.positions - b.positions).cwiseAbs().maxCoeff(),
              tolerance * a.positions.cwiseAbs().maxCoeff())
        << what;
  ASSERT_TRUE(b.has_normals()) << what;
  EXPECT_EQ(a.normals, b.normals) << what;
  for (const char* name : {"red", "green", "blue", "intensity"}) {
    ASSERT_NE(extra(b, name), nullptr) << what << ": " << name;
    if (tolerance == 0.0 || std::string(name) != "intensity")
      EXPECT_EQ(extra(a, name)->values, extra(b, name)->values) << what << ": " << name;
  }
}

TEST_F(PclTools, PclReadsEveryPcdEncodingWeWrite) {
  const PointCloud c = cloud();
  for (const char* encoding : {"ascii", "binary", "binary_compressed"}) {
    WriteOptions options;
    options.encoding =
        std::string(encoding) == "ascii" ? PlyEncoding::Ascii : PlyEncoding::BinaryLittleEndian;
    options.compressed = std::string(encoding) == "binary_compressed";
    const std::string pcd = path(std::string(encoding) + ".pcd");
    write_point_cloud(pcd, c, options);
    const std::string ply = path(std::string(encoding) + ".ply");
    ASSERT_EQ(run("pcl_pcd2ply -format 1 " + pcd + " " + ply), 0) << encoding;
    ASSERT_TRUE(fs::exists(ply)) << encoding;
    expect_same_points(c, read_point_cloud(ply), std::string("pcl_pcd2ply of ") + encoding);
  }
}

TEST_F(PclTools, WeReadThePcdFilesPclWrites) {
  const PointCloud c = cloud();
  write_point_cloud(path("in.ply"), c);
  for (const char* format : {"0", "1"}) {  // ascii, binary
    const std::string pcd = path(std::string("pcl") + format + ".pcd");
    ASSERT_EQ(run("pcl_ply2pcd -format " + std::string(format) + " " + path("in.ply") + " " + pcd),
              0);
    expect_same_points(c, read_point_cloud(pcd), std::string("pcl_ply2pcd -format ") + format,
                       std::string(format) == "0" ? 1e-7 : 0.0);
  }
}

}  // namespace
}  // namespace detexture
