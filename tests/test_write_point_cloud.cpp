// Writing PLY and XYZ files: round trips that must be exact, bytes that can be
// checked by hand, and the safety of the temporary-file-then-rename scheme.
#include "detexture/io/write_point_cloud.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "detexture/io/read_point_cloud.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards.
class WriteTempDir {
 public:
  WriteTempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info->name();  // "Test/Param" for parameterized tests
    for (char& c : name)
      if (c == '/') c = '_';
    std::random_device device;
    path_ =
        fs::temp_directory_path() / ("detexture_write_" + name + "_" + std::to_string(device()));
    fs::create_directories(path_);
  }
  ~WriteTempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

  // Names of the entries of the folder.
  std::set<std::string> listing() const {
    std::set<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_))
      names.insert(entry.path().filename().string());
    return names;
  }

 private:
  fs::path path_;
};

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void put_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string write_error(const std::string& path, const PointCloud& cloud,
                        const WriteOptions& options = {}) {
  try {
    write_point_cloud(path, cloud, options);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

PointCloud simple_cloud() {
  PointCloud cloud;
  cloud.positions.resize(2, 3);
  cloud.positions << 0, 0, 0, 1, 2, 3;
  return cloud;
}

// Three points whose coordinates need all 17 significant digits, extremes of
// every scalar type as extras, and an element of every property kind.
PointCloud every_type_cloud() {
  PointCloud cloud;
  cloud.positions.resize(3, 3);
  cloud.positions << 0.1, -1.0 / 3.0, 1e-300,  //
      -1e300, 123456789.123456789, -0.0,       //
      5e-324, 1.0 / 7.0, 2.0 / 3.0;
  cloud.normals.resize(3, 3);
  cloud.normals << 1, 2, 3, 0, 0, 1, -1, 0, 0;
  cloud.normals.row(0).normalize();
  using L8 = std::numeric_limits<std::int8_t>;
  using L16 = std::numeric_limits<std::int16_t>;
  using L32 = std::numeric_limits<std::int32_t>;
  cloud.extras = {
      {"i8", ScalarType::Int8, {L8::min(), L8::max(), 0}},
      {"u8", ScalarType::UInt8, {0, 255, 7}},
      {"i16", ScalarType::Int16, {L16::min(), L16::max(), -1}},
      {"u16", ScalarType::UInt16, {0, 65535, 1}},
      {"i32", ScalarType::Int32, {L32::min(), L32::max(), -5}},
      {"u32", ScalarType::UInt32, {0, 4294967295.0, 3}},
      {"f32", ScalarType::Float32, {0.1f, -FLT_MAX, FLT_TRUE_MIN}},
      {"f64", ScalarType::Float64, {0.1, DBL_MAX, -DBL_TRUE_MIN}},
  };
  OtherElement face;
  face.name = "face";
  face.properties = {{"vertex_indices", ScalarType::Int32, true, ScalarType::UInt8},
                     {"flags", ScalarType::UInt16, false, ScalarType::UInt8}};
  face.row_offsets = {0, 5, 11};
  face.values = {3, 0, 1, 2, 9, 4, 0, 1, 2, 0, 65535};
  OtherElement misc;
  misc.name = "misc";
  misc.properties = {{"a", ScalarType::Int8, false, ScalarType::UInt8},
                     {"b", ScalarType::Float32, true, ScalarType::UInt32},
                     {"c", ScalarType::Float64, true, ScalarType::Int16},
                     {"d", ScalarType::UInt32, false, ScalarType::UInt8}};
  // Row 1: a=-7, b=[0.5, -0.25], c=[], d=4294967295. Row 2: a=127, b=[], c=[0.1], d=12.
  misc.row_offsets = {0, 6, 11};
  misc.values = {-7, 2, 0.5, -0.25, 0, 4294967295.0, 127, 0, 1, 0.1, 12};
  cloud.other_elements = {face, misc};
  cloud.comments = {"made by detexture tests", "obj_info kept as a comment", " leading blank"};
  return cloud;
}

void expect_same_cloud(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  for (Eigen::Index i = 0; i < a.positions.rows(); ++i)
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(a.positions(i, d), b.positions(i, d)) << "point " << i << " axis " << d;
      EXPECT_EQ(std::signbit(a.positions(i, d)), std::signbit(b.positions(i, d)));
    }
  ASSERT_EQ(a.has_normals(), b.has_normals());
  EXPECT_EQ(a.normals, b.normals);
  ASSERT_EQ(a.extras.size(), b.extras.size());
  for (std::size_t k = 0; k < a.extras.size(); ++k) {
    EXPECT_EQ(a.extras[k].name, b.extras[k].name);
    EXPECT_EQ(a.extras[k].type, b.extras[k].type) << a.extras[k].name;
    EXPECT_EQ(a.extras[k].values, b.extras[k].values) << a.extras[k].name;
  }
  ASSERT_EQ(a.other_elements.size(), b.other_elements.size());
  for (std::size_t k = 0; k < a.other_elements.size(); ++k) {
    const OtherElement& ea = a.other_elements[k];
    const OtherElement& eb = b.other_elements[k];
    EXPECT_EQ(ea.name, eb.name);
    ASSERT_EQ(ea.properties.size(), eb.properties.size());
    for (std::size_t p = 0; p < ea.properties.size(); ++p) {
      EXPECT_EQ(ea.properties[p].name, eb.properties[p].name);
      EXPECT_EQ(ea.properties[p].type, eb.properties[p].type);
      EXPECT_EQ(ea.properties[p].is_list, eb.properties[p].is_list);
      if (ea.properties[p].is_list) {
        EXPECT_EQ(ea.properties[p].count_type, eb.properties[p].count_type);
      }
    }
    EXPECT_EQ(ea.row_offsets, eb.row_offsets) << ea.name;
    EXPECT_EQ(ea.values, eb.values) << ea.name;
  }
  EXPECT_EQ(a.comments, b.comments);
}

class PlyRoundTrip : public ::testing::TestWithParam<PlyEncoding> {};

TEST_P(PlyRoundTrip, EveryScalarTypeKeepsValuesAndTypes) {
  WriteTempDir dir;
  const PointCloud cloud = every_type_cloud();
  const std::string path = dir.file("all.ply");
  WriteOptions options;
  options.encoding = GetParam();
  write_point_cloud(path, cloud, options);
  ReadReport report;
  const PointCloud back = read_point_cloud(path, FileFormat::Auto, &report);
  expect_same_cloud(cloud, back);
  EXPECT_TRUE(report.notices.empty());
  EXPECT_EQ(report.zero_length_normals, 0u);
}

TEST_P(PlyRoundTrip, MeshReadFromAsciiKeepsFacesWhenWrittenAgain) {
  WriteTempDir dir;
  const std::string input = dir.file("in.ply");
  put_file(input,
           "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nproperty uchar red\nelement face 2\n"
           "property list uchar int vertex_indices\nend_header\n"
           "0 0 0 10\n1 0 0 20\n1 1 0 30\n0 1 0 40\n3 0 1 2\n3 0 2 3\n");
  const PointCloud mesh = read_point_cloud(input);
  WriteOptions options;
  options.encoding = GetParam();
  const std::string output = dir.file("out.ply");
  write_point_cloud(output, mesh, options);
  const PointCloud back = read_point_cloud(output);
  expect_same_cloud(mesh, back);
  ASSERT_EQ(back.other_elements.size(), 1u);
  EXPECT_EQ(back.other_elements[0].values, (std::vector<double>{3, 0, 1, 2, 3, 0, 2, 3}));
  EXPECT_EQ(back.extras[0].values, (std::vector<double>{10, 20, 30, 40}));
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, PlyRoundTrip,
                         ::testing::Values(PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian,
                                           PlyEncoding::BinaryBigEndian),
                         [](const ::testing::TestParamInfo<PlyEncoding>& info) {
                           return info.param == PlyEncoding::Ascii ? std::string("Ascii")
                                  : info.param == PlyEncoding::BinaryLittleEndian
                                      ? std::string("BinaryLittleEndian")
                                      : std::string("BinaryBigEndian");
                         });

TEST(WritePly, BigEndianBytesAreKnown) {
  WriteTempDir dir;
  PointCloud cloud;
  cloud.positions.resize(1, 3);
  cloud.positions << 1.0, -2.0, 0.5;
  cloud.extras = {{"s", ScalarType::Int16, {-2}}};
  const std::string path = dir.file("be.ply");
  WriteOptions options;
  options.encoding = PlyEncoding::BinaryBigEndian;
  write_point_cloud(path, cloud, options);
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty double x\n"
      "property double y\nproperty double z\nproperty short s\nend_header\n";
  const unsigned char data[] = {0x3F, 0xF0, 0, 0, 0, 0, 0, 0,  // 1.0
                                0xC0, 0x00, 0, 0, 0, 0, 0, 0,  // -2.0
                                0x3F, 0xE0, 0, 0, 0, 0, 0, 0,  // 0.5
                                0xFF, 0xFE};                   // -2
  EXPECT_EQ(file_bytes(path),
            header + std::string(reinterpret_cast<const char*>(data), sizeof data));
}

TEST(WritePly, AsciiUsesShortestExactText) {
  WriteTempDir dir;
  PointCloud cloud;
  cloud.positions.resize(1, 3);
  cloud.positions << 0.1, 1.0 / 3.0, -2;
  cloud.extras = {{"f", ScalarType::Float32, {0.1f}}, {"c", ScalarType::UInt8, {255}}};
  const std::string path = dir.file("a.ply");
  WriteOptions options;
  options.encoding = PlyEncoding::Ascii;
  write_point_cloud(path, cloud, options);
  const std::string text = file_bytes(path);
  EXPECT_NE(text.find("end_header\n0.1 0.3333333333333333 -2 0.1 255\n"), std::string::npos)
      << text;
}

TEST(WriteXyz, RoundTripsFullPrecisionWithNormalsAndExtras) {
  WriteTempDir dir;
  PointCloud cloud = every_type_cloud();
  cloud.extras = {{"field6", ScalarType::Float64, {0.1, -1e-310, 7}}};
  cloud.other_elements.clear();
  cloud.comments.clear();
  const std::string path = dir.file("a.xyzn");
  write_point_cloud(path, cloud);
  expect_same_cloud(cloud, read_point_cloud(path));
}

TEST(WriteXyz, PwnIsWrittenAsSixColumns) {
  WriteTempDir dir;
  PointCloud cloud = simple_cloud();
  cloud.normals = Normals::Zero(2, 3);
  cloud.normals(0, 2) = 1;
  cloud.normals(1, 0) = -1;
  const std::string path = dir.file("a.pwn");
  write_point_cloud(path, cloud);
  EXPECT_EQ(file_bytes(path), "0 0 0 0 0 1\n1 2 3 -1 0 0\n");
  expect_same_cloud(cloud, read_point_cloud(path));
}

TEST(WriteXyz, WithoutNormalsWritesThreeColumnsAndCsvUsesCommas) {
  WriteTempDir dir;
  PointCloud cloud = simple_cloud();
  cloud.positions(0, 0) = 0.1;
  cloud.extras = {{"red", ScalarType::UInt8, {1, 2}}};
  const std::string xyz = dir.file("a.xyz"), csv = dir.file("a.csv");
  write_point_cloud(xyz, cloud);
  write_point_cloud(csv, cloud);
  EXPECT_EQ(file_bytes(xyz), "0.1 0 0\n1 2 3\n");
  EXPECT_EQ(file_bytes(csv), "0.1,0,0\n1,2,3\n");
  EXPECT_EQ(read_point_cloud(csv).positions, cloud.positions);
}

TEST(WritePointCloud, RefusesToOverwriteTheProtectedInput) {
  WriteTempDir dir;
  fs::create_directory(dir.path() / "sub");
  const std::string input = dir.file("in.ply");
  write_point_cloud(input, simple_cloud());
  const std::string original = file_bytes(input);
  fs::create_symlink(input, dir.file("link.ply"));
  PointCloud other = simple_cloud();
  other.positions(0, 0) = 42;
  WriteOptions options;
  options.protect_path = input;
  for (const std::string& target :
       {input, (dir.path() / "." / "in.ply").string(),
        (dir.path() / "sub" / ".." / "in.ply").string(), dir.file("link.ply")}) {
    const std::string message = write_error(target, other, options);
    EXPECT_NE(message.find(target), std::string::npos) << message;
    EXPECT_NE(message.find("input"), std::string::npos) << message;
  }
  EXPECT_EQ(file_bytes(input), original);
  EXPECT_EQ(dir.listing(), (std::set<std::string>{"in.ply", "link.ply", "sub"}));
  // Another target is fine.
  write_point_cloud(dir.file("out.ply"), other, options);
  EXPECT_EQ(read_point_cloud(dir.file("out.ply")).positions(0, 0), 42);
}

TEST(WritePointCloud, LeavesNoTemporaryFiles) {
  WriteTempDir dir;
  const std::string path = dir.file("out.ply");
  write_point_cloud(path, simple_cloud());
  EXPECT_EQ(dir.listing(), std::set<std::string>{"out.ply"});
  // Writing over an existing file replaces it.
  PointCloud other = simple_cloud();
  other.positions(1, 2) = -9;
  write_point_cloud(path, other);
  EXPECT_EQ(read_point_cloud(path).positions(1, 2), -9);
  EXPECT_EQ(dir.listing(), std::set<std::string>{"out.ply"});
}

TEST(WritePointCloud, FailureKeepsTheExistingFileAndLeavesNoTemporary) {
  WriteTempDir dir;
  const std::string path = dir.file("out.ply");
  put_file(path, "previous contents");

  PointCloud bad_extra = simple_cloud();
  bad_extra.extras = {{"red", ScalarType::UInt8, {0, 300}}};
  std::string message = write_error(path, bad_extra);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("'red'"), std::string::npos) << message;
  EXPECT_NE(message.find("uchar"), std::string::npos) << message;

  // Fails after the vertex rows have been written to the temporary file.
  PointCloud bad_face = simple_cloud();
  OtherElement face;
  face.name = "face";
  face.properties = {{"vertex_indices", ScalarType::Int32, true, ScalarType::UInt8}};
  face.row_offsets = {0, 4, 6};
  face.values = {3, 0, 1, 1, 3, 0};  // the second row announces 3 indices and has 1
  bad_face.other_elements = {face};
  message = write_error(path, bad_face);
  EXPECT_NE(message.find("row 2 of element 'face'"), std::string::npos) << message;

  EXPECT_EQ(file_bytes(path), "previous contents");
  EXPECT_EQ(dir.listing(), std::set<std::string>{"out.ply"});
}

TEST(WritePointCloud, AfterAFailedReadNoFileIsWritten) {
  WriteTempDir dir;
  const std::string input = dir.file("bad.xyz"), output = dir.file("out.ply");
  put_file(input, "1 2 3\n4 5\n");
  EXPECT_THROW(
      {
        const PointCloud cloud = read_point_cloud(input);
        write_point_cloud(output, cloud);
      },
      std::runtime_error);
  EXPECT_FALSE(fs::exists(output));
  EXPECT_EQ(dir.listing(), std::set<std::string>{"bad.xyz"});
}

TEST(WritePointCloud, BadTargetsAndCloudsThrowNamingTheFile) {
  WriteTempDir dir;
  const std::string unknown = dir.file("out.las");
  EXPECT_NE(write_error(unknown, simple_cloud()).find(unknown), std::string::npos);
  const std::string missing_folder = dir.file("missing/out.ply");
  EXPECT_NE(write_error(missing_folder, simple_cloud()).find(missing_folder), std::string::npos);
  const std::string empty = dir.file("empty.ply");
  EXPECT_NE(write_error(empty, PointCloud{}).find("empty"), std::string::npos);
  PointCloud nan_point = simple_cloud();
  nan_point.positions(1, 1) = std::nan("");
  EXPECT_NE(write_error(empty, nan_point).find("point 1"), std::string::npos);
  PointCloud clash = simple_cloud();
  clash.extras = {{"x", ScalarType::Float32, {0, 0}}};
  EXPECT_NE(write_error(empty, clash).find("'x'"), std::string::npos);
  EXPECT_EQ(dir.listing(), std::set<std::string>{});
  // The format argument overrides the extension.
  WriteOptions options;
  options.format = FileFormat::Xyz;
  write_point_cloud(unknown, simple_cloud(), options);
  EXPECT_EQ(file_bytes(unknown), "0 0 0\n1 2 3\n");
}

}  // namespace
}  // namespace detexture

namespace detexture {
namespace {

// A float cloud stays a float cloud: the output is not twice the input's size.
TEST(PlyRoundTrip, SinglePrecisionPositionsStaySingle) {
  const auto dir = std::filesystem::temp_directory_path() / "detexture_single_precision";
  std::filesystem::create_directories(dir);
  PointCloud cloud;
  cloud.positions.resize(2, 3);
  cloud.positions << 0.5, 0.25, 1.0, 2.0, 3.0, 4.0;
  cloud.normals.resize(2, 3);
  cloud.normals << 0, 0, 1, 1, 0, 0;
  cloud.position_type = cloud.normal_type = ScalarType::Float32;
  const std::string a = (dir / "a.ply").string(), b = (dir / "b.ply").string();
  write_point_cloud(a, cloud);
  const PointCloud back = read_point_cloud(a);
  EXPECT_EQ(back.position_type, ScalarType::Float32);
  EXPECT_EQ(back.normal_type, ScalarType::Float32);
  EXPECT_EQ(back.positions, cloud.positions);
  write_point_cloud(b, back);
  EXPECT_EQ(std::filesystem::file_size(a), std::filesystem::file_size(b));
  cloud.position_type = cloud.normal_type = ScalarType::Float64;
  write_point_cloud(b, cloud);
  EXPECT_EQ(read_point_cloud(b).position_type, ScalarType::Float64);
  EXPECT_GT(std::filesystem::file_size(b), std::filesystem::file_size(a));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace detexture
