// Reading PLY and XYZ files written byte by byte by the tests themselves, so
// every expected value can be checked by hand.
#include "detexture/io/read_point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace detexture {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards.
class ReadTempDir {
 public:
  ReadTempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info->name();  // "Test/Param" for parameterized tests
    for (char& c : name)
      if (c == '/') c = '_';
    std::random_device device;
    path_ = fs::temp_directory_path() / ("detexture_read_" + name + "_" + std::to_string(device()));
    fs::create_directories(path_);
  }
  ~ReadTempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

  // Write bytes to a file of this folder and return its path.
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

 private:
  fs::path path_;
};

std::string bytes(std::initializer_list<unsigned> values) {
  std::string s;
  for (unsigned v : values) s += static_cast<char>(v);
  return s;
}

// The message of the std::runtime_error that reading path throws ("" if none).
std::string read_error(const std::string& path, FileFormat format = FileFormat::Auto) {
  try {
    read_point_cloud(path, format);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

const std::string kBinaryHeaderTypes =
    "element vertex 2\n"
    "property float x\nproperty float y\nproperty float z\n"
    "property short s\nproperty uint u\nproperty double d\n"
    "end_header\n";

void expect_known_binary_values(const PointCloud& cloud) {
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.positions(0, 0), 1.0);
  EXPECT_EQ(cloud.positions(0, 1), -2.0);
  EXPECT_EQ(cloud.positions(0, 2), 0.5);
  EXPECT_EQ(cloud.positions(1, 0), 0.0);
  EXPECT_EQ(cloud.positions(1, 1), 2.5);
  EXPECT_EQ(cloud.positions(1, 2), -0.25);
  EXPECT_FALSE(cloud.has_normals());
  ASSERT_EQ(cloud.extras.size(), 3u);
  EXPECT_EQ(cloud.extras[0].name, "s");
  EXPECT_EQ(cloud.extras[0].type, ScalarType::Int16);
  EXPECT_EQ(cloud.extras[0].values, (std::vector<double>{-2, 258}));
  EXPECT_EQ(cloud.extras[1].name, "u");
  EXPECT_EQ(cloud.extras[1].type, ScalarType::UInt32);
  EXPECT_EQ(cloud.extras[1].values, (std::vector<double>{16909060, 4294967295.0}));
  EXPECT_EQ(cloud.extras[2].name, "d");
  EXPECT_EQ(cloud.extras[2].type, ScalarType::Float64);
  EXPECT_EQ(cloud.extras[2].values, (std::vector<double>{1.0, -2.0}));
}

TEST(ReadPly, BigEndianKnownBytes) {
  ReadTempDir dir;
  const std::string data =
      // 1.0f, -2.0f, 0.5f, short -2, uint 0x01020304, double 1.0
      bytes({0x3F, 0x80, 0, 0, 0xC0, 0, 0, 0, 0x3F, 0, 0, 0, 0xFF, 0xFE, 1, 2, 3, 4}) +
      bytes({0x3F, 0xF0, 0, 0, 0, 0, 0, 0}) +
      // 0.0f, 2.5f, -0.25f, short 258, uint 0xFFFFFFFF, double -2.0
      bytes({0, 0, 0, 0, 0x40, 0x20, 0, 0, 0xBE, 0x80, 0, 0, 0x01, 0x02, 0xFF, 0xFF, 0xFF, 0xFF}) +
      bytes({0xC0, 0, 0, 0, 0, 0, 0, 0});
  const std::string path =
      dir.write("be.ply", "ply\nformat binary_big_endian 1.0\n" + kBinaryHeaderTypes + data);
  expect_known_binary_values(read_point_cloud(path));
}

TEST(ReadPly, LittleEndianKnownBytes) {
  ReadTempDir dir;
  const std::string data =
      bytes({0, 0, 0x80, 0x3F, 0, 0, 0, 0xC0, 0, 0, 0, 0x3F, 0xFE, 0xFF, 4, 3, 2, 1}) +
      bytes({0, 0, 0, 0, 0, 0, 0xF0, 0x3F}) +
      bytes({0, 0, 0, 0, 0, 0, 0x20, 0x40, 0, 0, 0x80, 0xBE, 0x02, 0x01, 0xFF, 0xFF, 0xFF, 0xFF}) +
      bytes({0, 0, 0, 0, 0, 0, 0, 0xC0});
  const std::string path =
      dir.write("le.ply", "ply\nformat binary_little_endian 1.0\n" + kBinaryHeaderTypes + data);
  expect_known_binary_values(read_point_cloud(path));
}

TEST(ReadPly, AsciiWithCrlfCommentsAndBothTypeSpellings) {
  ReadTempDir dir;
  const std::string path = dir.write(
      "crlf.ply",
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info scanner 3\r\n"
      "element vertex 2\r\nproperty float32 x\r\nproperty int16 y\r\nproperty double z\r\n"
      "property uint8 red\r\nproperty int8 label\r\nend_header\r\n"
      "1.5 -2 3 255 -128\r\n+0.25 7 -1e-3 0 127\r\n");
  const PointCloud cloud = read_point_cloud(path);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.positions.row(0), Eigen::RowVector3d(1.5, -2, 3));
  EXPECT_EQ(cloud.positions.row(1), Eigen::RowVector3d(0.25, 7, -1e-3));
  ASSERT_EQ(cloud.extras.size(), 2u);
  EXPECT_EQ(cloud.extras[0].name, "red");
  EXPECT_EQ(cloud.extras[0].type, ScalarType::UInt8);
  EXPECT_EQ(cloud.extras[0].values, (std::vector<double>{255, 0}));
  EXPECT_EQ(cloud.extras[1].type, ScalarType::Int8);
  EXPECT_EQ(cloud.extras[1].values, (std::vector<double>{-128, 127}));
  EXPECT_EQ(cloud.comments, (std::vector<std::string>{"made by hand", "obj_info scanner 3"}));
}

TEST(ReadPly, Float32ValuesAreRoundedToFloat) {
  ReadTempDir dir;
  const std::string path = dir.write("f.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                     "property float y\nproperty float z\nproperty float i\n"
                                     "end_header\n0.1 0 0 0.1\n");
  const PointCloud cloud = read_point_cloud(path);
  EXPECT_EQ(cloud.positions(0, 0), static_cast<double>(0.1f));
  EXPECT_EQ(cloud.extras[0].values[0], static_cast<double>(0.1f));
}

TEST(ReadPly, MeshElementsAreCarriedThrough) {
  ReadTempDir dir;
  const std::string path =
      dir.write("mesh.ply",
                "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                "element edge 1\nproperty int vertex1\nproperty int vertex2\nproperty uchar red\n"
                "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n0 2 200\n");
  const PointCloud cloud = read_point_cloud(path);
  ASSERT_EQ(cloud.size(), 4u);
  ASSERT_EQ(cloud.other_elements.size(), 2u);
  const OtherElement& face = cloud.other_elements[0];
  EXPECT_EQ(face.name, "face");
  ASSERT_EQ(face.properties.size(), 1u);
  EXPECT_TRUE(face.properties[0].is_list);
  EXPECT_EQ(face.properties[0].count_type, ScalarType::UInt8);
  EXPECT_EQ(face.properties[0].type, ScalarType::Int32);
  EXPECT_EQ(face.size(), 2u);
  EXPECT_EQ(face.row_offsets, (std::vector<std::uint64_t>{0, 4, 8}));
  EXPECT_EQ(face.values, (std::vector<double>{3, 0, 1, 2, 3, 0, 2, 3}));
  const OtherElement& edge = cloud.other_elements[1];
  EXPECT_EQ(edge.name, "edge");
  EXPECT_EQ(edge.properties.size(), 3u);
  EXPECT_EQ(edge.row_offsets, (std::vector<std::uint64_t>{0, 3}));
  EXPECT_EQ(edge.values, (std::vector<double>{0, 2, 200}));
}

TEST(ReadPly, VertexListPropertyIsSkippedWithNotice) {
  ReadTempDir dir;
  const std::string path = dir.write(
      "list.ply",
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property list uchar float weights\nproperty float z\nproperty ushort id\nend_header\n"
      "1 2 3 0.1 0.2 0.3 3 7\n4 5 0 6 8\n");
  ReadReport report;
  const PointCloud cloud = read_point_cloud(path, FileFormat::Auto, &report);
  EXPECT_EQ(cloud.positions.row(0), Eigen::RowVector3d(1, 2, 3));
  EXPECT_EQ(cloud.positions.row(1), Eigen::RowVector3d(4, 5, 6));
  ASSERT_EQ(cloud.extras.size(), 1u);
  EXPECT_EQ(cloud.extras[0].values, (std::vector<double>{7, 8}));
  ASSERT_EQ(report.notices.size(), 1u);
  EXPECT_NE(report.notices[0].find("weights"), std::string::npos);
}

TEST(ReadPly, NormalsAreNormalizedAndZeroOrNanOnesCounted) {
  ReadTempDir dir;
  const std::string path = dir.write(
      "n.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n"
      "0 0 0 0 0 2\n1 0 0 3 4 0\n2 0 0 0 0 0\n3 0 0 nan 0 1\n");
  ReadReport report;
  const PointCloud cloud = read_point_cloud(path, FileFormat::Auto, &report);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals.row(0), Eigen::RowVector3d(0, 0, 1));
  EXPECT_DOUBLE_EQ(cloud.normals(1, 0), 0.6);
  EXPECT_DOUBLE_EQ(cloud.normals(1, 1), 0.8);
  EXPECT_EQ(cloud.normals(1, 2), 0.0);
  EXPECT_EQ(cloud.normals.row(2), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(cloud.normals.row(3), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(report.zero_length_normals, 2u);
}

TEST(ReadPly, PartialNormalsAreKeptAsExtras) {
  ReadTempDir dir;
  const std::string path =
      dir.write("p.ply",
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n"
                "property double z\nproperty float nx\nend_header\n1 2 3 4\n");
  ReadReport report;
  const PointCloud cloud = read_point_cloud(path, FileFormat::Auto, &report);
  EXPECT_FALSE(cloud.has_normals());
  ASSERT_EQ(cloud.extras.size(), 1u);
  EXPECT_EQ(cloud.extras[0].name, "nx");
  EXPECT_EQ(report.notices.size(), 1u);
}

TEST(ReadXyz, SpacesCommasCommentsAndBlankLines) {
  ReadTempDir dir;
  const std::string path = dir.write(
      "a.xyz", "# a comment\n1 2 3\n\n   \n  4,5,6  \n7 , 8 ,9 # trailing\r\n\t10\t11\t-1.5e2\n");
  const PointCloud cloud = read_point_cloud(path);
  ASSERT_EQ(cloud.size(), 4u);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_TRUE(cloud.extras.empty());
  EXPECT_EQ(cloud.positions.row(0), Eigen::RowVector3d(1, 2, 3));
  EXPECT_EQ(cloud.positions.row(1), Eigen::RowVector3d(4, 5, 6));
  EXPECT_EQ(cloud.positions.row(2), Eigen::RowVector3d(7, 8, 9));
  EXPECT_EQ(cloud.positions.row(3), Eigen::RowVector3d(10, 11, -150));
  // A spreadsheet's UTF-8 byte order mark is skipped.
  const std::string bom = dir.write("bom.csv",
                                    "\xEF\xBB\xBF"
                                    "1,2,3\n");
  EXPECT_EQ(read_point_cloud(bom).positions.row(0), Eigen::RowVector3d(1, 2, 3));
}

TEST(ReadXyz, PtsCountLineIsAcceptedAndChecked) {
  ReadTempDir dir;
  const std::string good = dir.write("good.pts", "3\n1 2 3\n4 5 6\n7 8 9\n");
  EXPECT_EQ(read_point_cloud(good).size(), 3u);
  const std::string bad = dir.write("bad.pts", "# scan\n4\n1 2 3\n4 5 6\n7 8 9\n");
  const std::string message = read_error(bad);
  EXPECT_NE(message.find(bad), std::string::npos) << message;
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
  EXPECT_NE(message.find("declares 4 points, but the file has 3"), std::string::npos) << message;
}

TEST(ReadXyz, NormalsAreNormalizedAndFurtherColumnsKeptAsFloat64) {
  ReadTempDir dir;
  const std::string path =
      dir.write("n.csv", "0,0,0,0,0,5,7.5,-1\n1,1,1,3,0,4,0.25,2\n2,2,2,0,0,0,0,0\n");
  ReadReport report;
  const PointCloud cloud = read_point_cloud(path, FileFormat::Auto, &report);
  ASSERT_EQ(cloud.size(), 3u);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals.row(0), Eigen::RowVector3d(0, 0, 1));
  EXPECT_DOUBLE_EQ(cloud.normals(1, 0), 0.6);
  EXPECT_DOUBLE_EQ(cloud.normals(1, 2), 0.8);
  EXPECT_EQ(cloud.normals.row(2), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(report.zero_length_normals, 1u);
  ASSERT_EQ(cloud.extras.size(), 2u);
  EXPECT_EQ(cloud.extras[0].name, "field6");
  EXPECT_EQ(cloud.extras[0].type, ScalarType::Float64);
  EXPECT_EQ(cloud.extras[0].values, (std::vector<double>{7.5, 0.25, 0}));
  EXPECT_EQ(cloud.extras[1].name, "field7");
  EXPECT_EQ(cloud.extras[1].values, (std::vector<double>{-1, 2, 0}));
}

// CGAL's examples name their text clouds with normals .pwn: x y z nx ny nz.
TEST(ReadXyz, PwnFilesAreReadWithTheirNormals) {
  ReadTempDir dir;
  const std::string path = dir.write("oni.pwn", "0 0 0 0 0 2\n1 0 0 0 -1 0\n");
  const PointCloud cloud = read_point_cloud(path);
  ASSERT_EQ(cloud.size(), 2u);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals.row(0), Eigen::RowVector3d(0, 0, 1));
  EXPECT_EQ(cloud.normals.row(1), Eigen::RowVector3d(0, -1, 0));
  EXPECT_TRUE(cloud.extras.empty());
}

TEST(ReadXyz, FormatArgumentOverridesExtension) {
  ReadTempDir dir;
  const std::string path = dir.write("cloud.dat", "1 2 3\n");
  EXPECT_EQ(read_point_cloud(path, FileFormat::Xyz).size(), 1u);
  EXPECT_NE(read_error(path).find("extension"), std::string::npos);
  // A PLY file named .xyz, read as PLY.
  const std::string ply =
      dir.write("ply.xyz",
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n1 2 3\n");
  EXPECT_EQ(read_point_cloud(ply, FileFormat::Ply).positions.row(0), Eigen::RowVector3d(1, 2, 3));
}

TEST(ReadFormat, FromExtensionAndName) {
  EXPECT_EQ(format_from_extension("a.ply"), FileFormat::Ply);
  EXPECT_EQ(format_from_extension("dir.v2/a.PLY"), FileFormat::Ply);
  for (const char* name : {"a.xyz", "a.XYZN", "a.pwn", "a.txt", "a.pts", "a.csv"})
    EXPECT_EQ(format_from_extension(name), FileFormat::Xyz) << name;
  EXPECT_EQ(format_from_extension("a.obj"), FileFormat::Obj);
  EXPECT_EQ(format_from_extension("a.OFF"), FileFormat::Off);
  EXPECT_EQ(format_from_extension("a.Stl"), FileFormat::Stl);
  EXPECT_EQ(format_from_extension("a.pcd"), FileFormat::Pcd);
  EXPECT_THROW(format_from_extension("a.las"), std::runtime_error);
  EXPECT_THROW(format_from_extension("noextension"), std::runtime_error);
  EXPECT_EQ(parse_file_format("auto"), FileFormat::Auto);
  EXPECT_EQ(parse_file_format("ply"), FileFormat::Ply);
  EXPECT_EQ(parse_file_format("xyz"), FileFormat::Xyz);
  EXPECT_EQ(parse_file_format("obj"), FileFormat::Obj);
  EXPECT_EQ(parse_file_format("pcd"), FileFormat::Pcd);
  EXPECT_THROW(parse_file_format("las"), std::invalid_argument);
}

// One class of bad input: the file's content, and text the error message must
// contain besides the file's path (the location, and what is wrong).
struct BadInput {
  const char* label;
  const char* file_name;
  std::string content;
  std::vector<std::string> expected;
};

std::string ply_ascii(const std::string& body_after_format) {
  return "ply\nformat ascii 1.0\n" + body_after_format;
}
const std::string kXyzHeader =
    "element vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n";

std::string binary_le_header(unsigned count) {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(count) +
         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

std::vector<BadInput> bad_inputs() {
  const std::string one_float = bytes({0, 0, 0x80, 0x3F});  // 1.0f little endian
  const std::string inf_float = bytes({0, 0, 0x80, 0x7F});  // +Inf little endian
  const std::string header2 = binary_le_header(2);
  const std::string list_header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int v\n"
      "end_header\n";
  return {
      {"no magic", "a.ply", "plx\nformat ascii 1.0\n", {"line 1", "'ply'"}},
      {"unknown format",
       "a.ply",
       "ply\nformat binary_middle_endian 1.0\n" + kXyzHeader,
       {"line 2", "binary_middle_endian"}},
      {"bad version", "a.ply", "ply\nformat ascii 2.0\n" + kXyzHeader, {"line 2", "version"}},
      {"missing format",
       "a.ply",
       "ply\nelement vertex 1\nproperty float x\nend_header\n",
       {"line 2", "format"}},
      {"unknown type",
       "a.ply",
       ply_ascii("element vertex 1\nproperty float x\nproperty float128 y\n"),
       {"line 5", "float128"}},
      // (before the first element an unknown line is kept as a comment)
      {"unknown keyword",
       "a.ply",
       ply_ascii("element vertex 1\nproperty float x\nelephant 1\n"),
       {"line 5", "elephant"}},
      {"missing end_header",
       "a.ply",
       ply_ascii("element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"),
       {"line 6", "end_header"}},
      {"element without properties",
       "a.ply",
       ply_ascii("element vertex 1\nelement face 0\nproperty list uchar int v\nend_header\n"),
       {"line 3", "no properties"}},
      {"bad element count", "a.ply", ply_ascii("element vertex -3\n"), {"line 3", "'-3'"}},
      {"property outside element", "a.ply", ply_ascii("property float x\n"), {"line 3"}},
      {"missing z",
       "a.ply",
       ply_ascii("comment c\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n"
                 "1 2\n"),
       {"line 4", "'z'"}},
      {"no vertex element",
       "a.ply",
       ply_ascii("element face 1\nproperty list uchar int v\nend_header\n3 0 1 2\n"),
       {"line 5", "vertex"}},
      {"empty cloud",
       "a.ply",
       ply_ascii("element vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                 "end_header\n"),
       {"line 3", "empty"}},
      {"too few ascii rows",
       "a.ply",
       ply_ascii(kXyzHeader + "1 2 3\n"),
       {"line 9", "after 1 of the 2 rows"}},
      {"trailing ascii data",
       "a.ply",
       ply_ascii(kXyzHeader + "1 2 3\n4 5 6\n\n7 8 9\n"),
       {"line 11", "after the last row"}},
      {"too few values",
       "a.ply",
       ply_ascii(kXyzHeader + "1 2 3\n4 5\n"),
       {"line 9", "too few values", "row 2 of 2"}},
      {"too many values",
       "a.ply",
       ply_ascii(kXyzHeader + "1 2 3 4\n4 5 6\n"),
       {"line 8", "4 values, more than the 3 properties"}},
      {"non-numeric token",
       "a.ply",
       ply_ascii(kXyzHeader + "1 2 3\n4 abc 6\n"),
       {"line 9", "'abc'", "'y'"}},
      {"value out of range",
       "a.ply",
       ply_ascii("element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                 "property uchar red\nend_header\n1 2 3 256\n"),
       {"line 9", "'256'", "uchar"}},
      {"nan coordinate", "a.ply", ply_ascii(kXyzHeader + "1 2 3\nnan 5 6\n"), {"line 9", "NaN"}},
      {"inf coordinate binary",
       "a.ply",
       header2 + one_float + one_float + one_float + one_float + inf_float + one_float,
       {"byte " + std::to_string(header2.size() + 12), "infinite"}},
      {"truncated binary",
       "a.ply",
       header2 + one_float + one_float + one_float + one_float,
       {"byte " + std::to_string(header2.size()), "truncated"}},
      {"huge declared count",
       "a.ply",
       binary_le_header(4000000000u) + one_float + one_float,
       {"byte " + std::to_string(binary_le_header(4000000000u).size()), "truncated"}},
      {"huge ascii count",
       "a.ply",
       ply_ascii("element vertex 18446744073709551615\nproperty float x\nproperty float y\n"
                 "property float z\nend_header\n1 2 3\n"),
       {"line 9", "does not match"}},
      // 200 indices announced, one given: the list starts 13 bytes into the data.
      {"truncated list",
       "a.ply",
       list_header + std::string(12, '\0') + bytes({200, 0, 0, 0, 1}),
       {"byte " + std::to_string(list_header.size() + 13), "truncated", "'v'"}},
      {"xyz non-numeric", "a.xyz", "1 2 3\n4 5 six\n", {"line 2", "'six'"}},
      {"xyz header line", "a.csv", "x,y,z\n1,2,3\n", {"line 1", "'x'"}},
      {"xyz nan", "a.xyz", "# c\n1 2 3\n4 nan 6\n", {"line 3", "NaN"}},
      {"xyz inf", "a.txt", "1 2 inf\n", {"line 1", "infinite"}},
      {"xyz four columns", "a.xyz", "1 2 3 4\n", {"line 1", "4 values"}},
      {"xyz inconsistent columns", "a.xyz", "1 2 3\n1 2 3 0 0 1\n", {"line 2", "6 values"}},
      {"xyz empty field", "a.csv", "1,,3\n", {"line 1", "empty field"}},
      {"xyz empty cloud", "a.xyz", "# only a comment\n\n", {"line 2", "empty"}},
      {"xyz empty file", "a.xyz", "", {"empty"}},
  };
}

TEST(ReadErrors, EachBadInputNamesFileAndLocation) {
  ReadTempDir dir;
  for (const BadInput& bad : bad_inputs()) {
    const std::string path = dir.write(bad.file_name, bad.content);
    const std::string message = read_error(path);
    ASSERT_FALSE(message.empty()) << bad.label << ": no error";
    EXPECT_NE(message.find(path), std::string::npos) << bad.label << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << bad.label << ": " << message;
    for (const std::string& part : bad.expected)
      EXPECT_NE(message.find(part), std::string::npos)
          << bad.label << ": '" << part << "' not in: " << message;
    fs::remove(path);
  }
}

TEST(ReadErrors, MissingFileDirectoryAndUnknownExtension) {
  ReadTempDir dir;
  const std::string missing = dir.file("missing.ply");
  EXPECT_NE(read_error(missing).find(missing), std::string::npos);
  EXPECT_NE(read_error(missing).find("does not exist"), std::string::npos);
  const std::string folder = dir.file("folder.ply");
  fs::create_directory(folder);
  EXPECT_NE(read_error(folder).find("directory"), std::string::npos);
  const std::string unknown = dir.write("cloud.las", "v 1 2 3\n");
  EXPECT_NE(read_error(unknown).find(unknown), std::string::npos);
}

// A small binary mesh with normals, an extra and a list property.
std::string sample_binary_ply() {
  std::string s =
      "ply\nformat binary_little_endian 1.0\ncomment sample\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\nproperty float nx\n"
      "property float ny\nproperty float nz\nproperty uchar red\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string one = bytes({0, 0, 0x80, 0x3F}), zero(4, '\0');
  for (int i = 0; i < 3; ++i) s += one + zero + one + zero + zero + one + bytes({200});
  s += bytes({3, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0});
  return s;
}

// Every prefix of a binary file and many corrupted copies must either read
// or throw std::runtime_error: never crash, hang or throw anything else.
TEST(ReadErrors, TruncatedAndCorruptedFilesThrowCleanly) {
  ReadTempDir dir;
  const std::string good = sample_binary_ply();
  const std::string path = dir.file("fuzz.ply");
  ASSERT_EQ(read_point_cloud(dir.write("fuzz.ply", good)).size(), 3u);
  for (std::size_t length = 0; length < good.size(); ++length) {
    dir.write("fuzz.ply", good.substr(0, length));
    EXPECT_THROW(read_point_cloud(path), std::runtime_error) << "prefix of " << length;
  }
  std::mt19937 rng(12345);
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int v\n"
      "end_header\n0 0 0 1\n1 0 0 2\n3 0 1 1\n";
  for (const std::string& sample : {good, ascii}) {
    for (int trial = 0; trial < 200; ++trial) {
      std::string corrupted = sample;
      const int changes = 1 + static_cast<int>(rng() % 4);
      for (int c = 0; c < changes; ++c)
        corrupted[rng() % corrupted.size()] = static_cast<char>(rng() % 256);
      dir.write("fuzz.ply", corrupted);
      try {
        read_point_cloud(path);
      } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      }
    }
  }
}

}  // namespace
}  // namespace detexture
