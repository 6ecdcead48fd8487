// OBJ, OFF, STL and PCD: files written by hand whose content can be checked
// line by line, round trips that must be exact, and refusals that name the
// file and the line or byte.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "detexture/io/face_list.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;

class FormatDir {
 public:
  FormatDir() {
    std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::random_device device;
    path_ = fs::temp_directory_path() / ("detexture_formats_" + name + std::to_string(device()));
    fs::create_directories(path_);
  }
  ~FormatDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(file(name), std::ios::binary) << bytes;
    return file(name);
  }
  std::string read(const std::string& name) const {
    std::ifstream in(file(name), std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  fs::path path_;
};

std::string read_error(const std::string& path) {
  try {
    read_point_cloud(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<std::vector<std::uint32_t>> polygons(const PointCloud& cloud) {
  const FaceList faces = face_list(cloud);
  std::vector<std::vector<std::uint32_t>> out;
  for (std::size_t f = 0; f < faces.size(); ++f)
    out.emplace_back(faces.indices.begin() + faces.offsets[f],
                     faces.indices.begin() + faces.offsets[f + 1]);
  return out;
}

// A unit square split into a triangle and a quad... rather: a pyramid of a
// quad base and four triangles, with unit normals and awkward coordinates.
PointCloud pyramid() {
  PointCloud c;
  c.positions.resize(5, 3);
  c.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.1 + 0.2, 1.0 / 3.0;
  c.normals.resize(5, 3);
  for (int i = 0; i < 5; ++i)
    c.normals.row(i) = (c.positions.row(i) - Eigen::RowVector3d(0.5, 0.5, 0.2)).normalized();
  FaceList faces;
  const std::uint32_t quad[] = {0, 3, 2, 1}, t[4][3] = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  faces.add(quad, 4);
  for (const auto& tri : t) faces.add(tri, 3);
  set_face_list(c, faces);
  return c;
}

void expect_same_mesh(const PointCloud& a, const PointCloud& b, bool normals = true) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.positions, b.positions);
  if (normals) EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(polygons(a), polygons(b));
}

TEST(Obj, ReadsVerticesNormalsPolygonsAndNegativeIndices) {
  FormatDir dir;
  const std::string path = dir.write("a.obj",
                                     "# a comment\n"
                                     "mtllib a.mtl\n"
                                     "o square\n"
                                     "v 0 0 0\nv 1 0 0\r\nv 1 1 0\nv 0 1 0 1.0\n"
                                     "vt 0 0\nvn 0 0 1\n"
                                     "usemtl red\n"
                                     "f 1/1/1 2/1/1 3/1/1 -1/1/1\n"
                                     "l 1 2\n");
  ReadReport report;
  const PointCloud c = read_point_cloud(path, FileFormat::Auto, &report);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c.positions.row(2), Eigen::RowVector3d(1, 1, 0));
  ASSERT_TRUE(c.has_normals());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(c.normals.row(i), Eigen::RowVector3d(0, 0, 1));
  EXPECT_EQ(polygons(c), (std::vector<std::vector<std::uint32_t>>{{0, 1, 2, 3}}));
  std::string notices;
  for (const auto& n : report.notices) notices += n + "\n";
  EXPECT_NE(notices.find("1 texture coordinates"), std::string::npos) << notices;
  EXPECT_NE(notices.find("'mtllib' (1), 'o' (1), 'usemtl' (1)"), std::string::npos) << notices;
  EXPECT_NE(notices.find("point and line"), std::string::npos) << notices;
}

TEST(Obj, ACreaseNormalLeavesOutTheNormalsAndColoursAreKept) {
  FormatDir dir;
  const std::string path =
      dir.write("crease.obj",
                "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nv 0 0 1 0.5 0.5 0.5\n"
                "vn 0 0 1\nvn 1 0 0\nf 1//1 2//1 3//1\nf 1//2 3//2 4//2\n");
  ReadReport report;
  const PointCloud c = read_point_cloud(path, FileFormat::Auto, &report);
  EXPECT_FALSE(c.has_normals());
  ASSERT_EQ(report.notices.size(), 1u);
  EXPECT_NE(report.notices[0].find("2 face corners give their vertex a second"), std::string::npos)
      << report.notices[0];
  ASSERT_EQ(c.extras.size(), 3u);
  EXPECT_EQ(c.extras[0].name, "red");
  EXPECT_EQ(c.extras[1].values, (std::vector<double>{0, 1, 0, 0.5}));
}

// A colour beyond float's range (found by fuzz_read_obj) stays a double, so
// the file written from it reads back instead of holding "inf".
TEST(Obj, AColourBeyondFloatRangeRoundTrips) {
  FormatDir dir;
  const std::string path =
      dir.write("huge.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 4.5e63\n");
  const PointCloud c = read_point_cloud(path);
  ASSERT_EQ(c.extras.size(), 3u);
  EXPECT_EQ(c.extras[2].type, ScalarType::Float64);
  EXPECT_EQ(c.extras[2].values[2], 4.5e63);
  write_point_cloud(dir.file("back.obj"), c);
  const PointCloud back = read_point_cloud(dir.file("back.obj"));
  ASSERT_EQ(back.extras.size(), 3u);
  EXPECT_EQ(back.extras[2].values, c.extras[2].values);
  EXPECT_EQ(read_point_cloud(dir.write("small.obj", "v 0 0 0 1 0 0\n")).extras[0].type,
            ScalarType::Float32);
}

TEST(Obj, RoundTripIsExact) {
  FormatDir dir;
  const PointCloud c = pyramid();
  write_point_cloud(dir.file("p.obj"), c);
  expect_same_mesh(c, read_point_cloud(dir.file("p.obj")));
  const std::string text = dir.read("p.obj");
  EXPECT_NE(text.find("\nf 1//1 4//4 3//3 2//2\n"), std::string::npos) << text;
  // Without faces, the i-th vn belongs to the i-th v.
  PointCloud points = c;
  points.other_elements.clear();
  write_point_cloud(dir.file("q.obj"), points);
  const PointCloud back = read_point_cloud(dir.file("q.obj"));
  EXPECT_EQ(back.normals, c.normals);
  EXPECT_FALSE(has_faces(back));
}

TEST(Obj, WritingSaysWhatIsLeftOut) {
  FormatDir dir;
  PointCloud c = pyramid();
  c.extras.push_back({"intensity", ScalarType::Float32, {1, 2, 3, 4, 5}});
  std::vector<std::string> notices;
  WriteOptions options;
  options.notices = &notices;
  write_point_cloud(dir.file("p.obj"), c, options);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_NE(notices[0].find("OBJ cannot hold the vertex properties intensity"), std::string::npos);
}

TEST(Obj, BadFilesNameTheLine) {
  FormatDir dir;
  EXPECT_NE(read_error(dir.write("a.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n"))
                .find("line 3: corner '3' refers to vertex 3, but 2 vertices"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("b.obj", "v 0 0\n")).find("line 1: a vertex with 2 values"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("c.obj", "v 0 0 nan\n")).find("line 1: a NaN"), std::string::npos);
  EXPECT_NE(read_error(dir.write("d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"))
                .find("line 4: '0' is not a face corner"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("e.obj", "# nothing\n")).find("no vertex"), std::string::npos);
}

TEST(Off, ReadsColoursNormalsAndPolygons) {
  FormatDir dir;
  const std::string path = dir.write("a.off",
                                     "CNOFF\n# comment\n4 2 5\n"
                                     "0 0 0  0 0 1  255 0 0\n1 0 0  0 0 1  0 255 0\n"
                                     "1 1 0  0 0 1  0 0 255\n0 1 0  0 0 1  7 7 7\n"
                                     "3 0 1 2\n3 0 2 3 1 0 0\n");
  ReadReport report;
  const PointCloud c = read_point_cloud(path, FileFormat::Auto, &report);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_TRUE(c.has_normals());
  ASSERT_EQ(c.extras.size(), 3u);
  EXPECT_EQ(c.extras[2].type, ScalarType::UInt8);
  EXPECT_EQ(c.extras[2].values, (std::vector<double>{0, 0, 255, 7}));
  EXPECT_EQ(polygons(c), (std::vector<std::vector<std::uint32_t>>{{0, 1, 2}, {0, 2, 3}}));
  ASSERT_EQ(report.notices.size(), 1u);
  EXPECT_NE(report.notices[0].find("colours of 1 faces"), std::string::npos);
}

TEST(Off, RoundTripIsExact) {
  FormatDir dir;
  PointCloud c = pyramid();
  c.extras = {{"red", ScalarType::UInt8, {1, 2, 3, 4, 5}},
              {"green", ScalarType::UInt8, {0, 0, 0, 0, 255}},
              {"blue", ScalarType::UInt8, {9, 9, 9, 9, 9}}};
  write_point_cloud(dir.file("p.off"), c);
  EXPECT_EQ(dir.read("p.off").substr(0, 14), "CNOFF\n5 5 0\n0 ");
  const PointCloud back = read_point_cloud(dir.file("p.off"));
  expect_same_mesh(c, back);
  ASSERT_EQ(back.extras.size(), 3u);
  EXPECT_EQ(back.extras[1].values, c.extras[1].values);
  EXPECT_EQ(back.extras[1].type, ScalarType::UInt8);
}

TEST(Off, BadFilesNameTheLine) {
  FormatDir dir;
  EXPECT_NE(read_error(dir.write("a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"))
                .find("line 6: face 0 refers to vertex '3'"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("b.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n")).find("more than the"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("c.off", "4OFF\n1 0 0\n0 0 0 0\n")).find("line 1"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("d.off", "OFF 3 0 0\n0 0 0\n1 0 0\n0 1          \n"))
                .find("line 4: vertex 2 has 2 values"),
            std::string::npos);
  EXPECT_NE(
      read_error(dir.write("e.off", "OFF 1 0 0\n0 0 0\n1 1 1\n")).find("line 3: unexpected data"),
      std::string::npos);
  // 4 x 2^62 faces would wrap around to 0 bytes in 64 bits.
  EXPECT_NE(
      read_error(dir.write("f.off", "OFF 1 4611686018427387904 0\n0 0 0\n")).find("more than the"),
      std::string::npos);
  // A face of 2^64 - 1 corners: corners + 1 wraps to 0 (the fuzzer's crash
  // of session 33); the reader must refuse it, not index past the line.
  EXPECT_NE(read_error(dir.write("g.off",
                                 "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n"
                                 "18446744073709551615 0 1 2\n"))
                .find("line 5: face 0 declares 18446744073709551615 corners, but only 3"),
            std::string::npos);
}

TEST(Stl, AsciiCornersAreWeldedByPosition) {
  FormatDir dir;
  const std::string path = dir.write("a.stl",
                                     "solid square\n"
                                     " facet normal 0 0 1\n  outer loop\n"
                                     "   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
                                     "  endloop\n endfacet\n"
                                     " facet normal 0 0 1\n  outer loop\n"
                                     "   vertex 0 0 -0\n   vertex 1 1 0\n   vertex 0 1 0\n"
                                     "  endloop\n endfacet\nendsolid square\n");
  const PointCloud c = read_point_cloud(path);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c.positions.row(3), Eigen::RowVector3d(0, 1, 0));
  EXPECT_EQ(polygons(c), (std::vector<std::vector<std::uint32_t>>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_FALSE(c.has_normals());
}

TEST(Stl, BinaryAndAsciiRoundTrips) {
  FormatDir dir;
  PointCloud c = pyramid();
  c.normals = Normals();
  // Ascii keeps doubles exactly; the quad becomes two triangles. STL has no
  // vertex list: the vertices come back in the order the triangles first
  // use them (0 3 2 1 4), and a second round trip changes nothing.
  WriteOptions ascii;
  ascii.encoding = PlyEncoding::Ascii;
  write_point_cloud(dir.file("first.stl"), c, ascii);
  const PointCloud a = read_point_cloud(dir.file("first.stl"));
  const int order[] = {0, 3, 2, 1, 4};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(a.positions.row(i), c.positions.row(order[i]));
  EXPECT_EQ(polygons(a), (std::vector<std::vector<std::uint32_t>>{
                             {0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {3, 2, 4}, {2, 1, 4}, {1, 0, 4}}));
  write_point_cloud(dir.file("a.stl"), a, ascii);
  expect_same_mesh(read_point_cloud(dir.file("a.stl")), a, false);
  // Binary: 84 + 50 * 6 bytes, floats; a "solid" start stays binary.
  write_point_cloud(dir.file("b.stl"), a);
  EXPECT_EQ(fs::file_size(dir.file("b.stl")), 84u + 50u * 6u);
  const PointCloud b = read_point_cloud(dir.file("b.stl"));
  EXPECT_EQ(b.position_type, ScalarType::Float32);
  EXPECT_EQ(polygons(b), polygons(a));
  EXPECT_EQ(b.positions, a.positions.cast<float>().cast<double>());
  std::string bytes = dir.read("b.stl");
  bytes.replace(0, 5, "solid");
  const PointCloud s = read_point_cloud(dir.write("s.stl", bytes));
  EXPECT_EQ(s.positions, b.positions);
  // And a binary round trip of the binary one changes nothing.
  write_point_cloud(dir.file("c.stl"), b);
  expect_same_mesh(read_point_cloud(dir.file("c.stl")), b, false);
}

TEST(Stl, BadFilesAreRefused) {
  FormatDir dir;
  std::string bytes(84 + 50 * 2 - 1, '\0');
  bytes[80] = 2;
  EXPECT_NE(read_error(dir.write("t.stl", bytes)).find("does not match the 2 triangles"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("a.stl",
                                 "solid x\n facet normal 0 0 1\n  outer loop\n"
                                 "   vertex 0 0 0\n   vertex 1 0 0\n  endloop\n"
                                 " endfacet\nendsolid\n"))
                .find("line 7: a facet ends with 2 corners"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("b.stl", "solid x\nendsolid x\n")).find("no facet"),
            std::string::npos);
  FormatDir out;
  PointCloud points = pyramid();
  points.other_elements.clear();
  EXPECT_THROW(write_point_cloud(out.file("p.stl"), points), std::runtime_error);
}

PointCloud colored_cloud() {
  PointCloud c = pyramid();
  c.other_elements.clear();
  c.position_type = ScalarType::Float32;
  c.normal_type = ScalarType::Float32;
  c.positions = c.positions.cast<float>().cast<double>();
  c.normals << 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, 0, -1;  // unit in float too
  c.extras = {{"intensity", ScalarType::Float32, {0.5, 1, 2, 3, 4}},
              {"label", ScalarType::UInt16, {0, 1, 65535, 3, 4}},
              {"red", ScalarType::UInt8, {255, 0, 0, 10, 20}},
              {"green", ScalarType::UInt8, {0, 255, 0, 30, 40}},
              {"blue", ScalarType::UInt8, {0, 0, 255, 50, 60}},
              {"depth", ScalarType::Float64, {1.0 / 3.0, 0, 0, 0, 1e300}}};
  return c;
}

TEST(Pcd, EveryEncodingRoundTripsExactly) {
  FormatDir dir;
  const PointCloud c = colored_cloud();
  for (const char* encoding : {"ascii", "binary", "binary_compressed"}) {
    WriteOptions options;
    options.encoding =
        std::string(encoding) == "ascii" ? PlyEncoding::Ascii : PlyEncoding::BinaryLittleEndian;
    options.compressed = std::string(encoding) == "binary_compressed";
    const std::string path = dir.file(std::string(encoding) + ".pcd");
    write_point_cloud(path, c, options);
    EXPECT_NE(dir.read(std::string(encoding) + ".pcd")
                  .find("FIELDS x y z normal_x normal_y normal_z rgb intensity label depth\n"),
              std::string::npos);
    EXPECT_NE(dir.read(std::string(encoding) + ".pcd").find("DATA " + std::string(encoding) + "\n"),
              std::string::npos);
    const PointCloud back = read_point_cloud(path);
    EXPECT_EQ(back.positions, c.positions) << encoding;
    EXPECT_EQ(back.normals, c.normals) << encoding;
    EXPECT_EQ(back.position_type, ScalarType::Float32);
    ASSERT_EQ(back.extras.size(), 6u) << encoding;
    // Colours are packed into rgb and come back last, as red green blue.
    const char* order[] = {"intensity", "label", "depth", "red", "green", "blue"};
    const int from[] = {0, 1, 5, 2, 3, 4};
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(back.extras[k].name, order[k]);
      EXPECT_EQ(back.extras[k].type, c.extras[from[k]].type) << order[k];
      EXPECT_EQ(back.extras[k].values, c.extras[from[k]].values) << encoding << " " << order[k];
    }
  }
}

TEST(Pcd, ReadsAHandWrittenFileAndDropsInvalidPoints) {
  FormatDir dir;
  const std::string path = dir.write("h.pcd",
                                     "# .PCD v0.7 - Point Cloud Data file format\n"
                                     "VERSION 0.7\nFIELDS x y z rgb _ hist\nSIZE 4 4 4 4 1 2\n"
                                     "TYPE F F F U U I\nCOUNT 1 1 1 1 1 2\nWIDTH 3\nHEIGHT 1\n"
                                     "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n"
                                     "1 2 3 16714243 0 -1 5\n"
                                     "nan nan nan 0 0 0 0\n"
                                     "4 5 6 66298 0 2 3\n");
  ReadReport report;
  const PointCloud c = read_point_cloud(path, FileFormat::Auto, &report);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions.row(1), Eigen::RowVector3d(4, 5, 6));
  ASSERT_EQ(c.extras.size(), 5u);
  EXPECT_EQ(c.extras[0].name, "hist_0");
  EXPECT_EQ(c.extras[1].values, (std::vector<double>{5, 3}));
  EXPECT_EQ(c.extras[2].values, (std::vector<double>{255, 1}));  // 0xFF0A03, 0x0102FA
  EXPECT_EQ(c.extras[3].values, (std::vector<double>{10, 2}));
  EXPECT_EQ(c.extras[4].values, (std::vector<double>{3, 250}));
  ASSERT_EQ(report.notices.size(), 1u);
  EXPECT_NE(report.notices[0].find("dropped 1 points"), std::string::npos);
  EXPECT_TRUE(c.comments.empty());
}

TEST(Pcd, BadFilesAreRefusedWithTheLineOrByte) {
  FormatDir dir;
  const std::string header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  EXPECT_NE(read_error(dir.write("a.pcd", header + "DATA binary\n" + std::string(23, '\0')))
                .find("truncated binary data"),
            std::string::npos);
  EXPECT_NE(
      read_error(dir.write("b.pcd", header + "DATA ascii\n1 2 3         \n")).find("ends after 1"),
      std::string::npos);
  EXPECT_NE(read_error(dir.write("c.pcd",
                                 "VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\n"
                                 "WIDTH 1\nDATA ascii\n1 2\n"))
                .find("no field 'z'"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("d.pcd", header + "DATA lzma\n")).find("line 9: DATA 'lzma'"),
            std::string::npos);
  std::string corrupt = header + "DATA binary_compressed\n";
  const unsigned char sizes[8] = {4, 0, 0, 0, 24, 0, 0, 0};
  corrupt.append(reinterpret_cast<const char*>(sizes), 8);
  corrupt += "\xff\xff\xff\xff";
  EXPECT_NE(read_error(dir.write("e.pcd", corrupt)).find("LZF compressed data is corrupt"),
            std::string::npos);
  std::string huge = header + "DATA binary_compressed\n";
  const unsigned char claim[8] = {4, 0, 0, 0, 0, 0, 0, 0x7f};
  huge.append(reinterpret_cast<const char*>(claim), 8);
  huge += "abcd";
  EXPECT_NE(read_error(dir.write("f.pcd", huge)).find("uncompressed size"), std::string::npos);
  EXPECT_NE(read_error(dir.write("g.pcd",
                                 "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE I I I\n"
                                 "WIDTH 1\nDATA ascii\n1 2 3\n"))
                .find("supported are"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("h.pcd",
                                 "VERSION 0.7\nFIELDS x y z x\nSIZE 4 4 4 4\n"
                                 "TYPE F F F F\nWIDTH 1\nDATA ascii\n1 2 3 4\n"))
                .find("two fields are named 'x'"),
            std::string::npos);
  EXPECT_NE(read_error(dir.write("i.pcd",
                                 "VERSION 0.7\nFIELDS x y z h h_1\nSIZE 4 4 4 4 4\n"
                                 "TYPE F F F F F\nCOUNT 1 1 1 2 1\nWIDTH 1\n"
                                 "DATA ascii\n1 2 3 4 5 6\n"))
                .find("would both be named 'h_1'"),
            std::string::npos);
}

TEST(Pcd, AColourBesideFieldsNamedRedStaysPacked) {
  FormatDir dir;
  const PointCloud c = read_point_cloud(
      dir.write("c.pcd",
                "VERSION 0.7\nFIELDS x y z rgb red\nSIZE 4 4 4 4 1\nTYPE F F F U U\n"
                "WIDTH 1\nDATA ascii\n1 2 3 16714243 9\n"));
  ASSERT_EQ(c.extras.size(), 2u);
  EXPECT_EQ(c.extras[0].name, "rgb");
  EXPECT_EQ(c.extras[0].values[0], 16714243.0);
  EXPECT_EQ(c.extras[1].name, "red");
}

// Debian's assimp-testmodels: the same model as OBJ, OFF and STL.
TEST(MeshFormats, AssimpWusonIsTheSameMeshInEveryFormat) {
  const fs::path root = "/usr/share/assimp/models";
  if (!fs::exists(root / "OBJ/WusonOBJ.obj")) GTEST_SKIP() << "assimp-testmodels is not installed";
  const PointCloud obj = read_point_cloud((root / "OBJ/WusonOBJ.obj").string());
  const PointCloud stl = read_point_cloud((root / "STL/Wuson.stl").string());
  const PointCloud off = read_point_cloud((root / "OFF/Wuson.off").string());
  EXPECT_EQ(obj.size(), 2117u);
  EXPECT_EQ(stl.size(), 2117u);  // welded from 3 x 3732 corners
  EXPECT_EQ(off.size(), 3205u);  // the OFF file repeats vertices, kept as they are
  EXPECT_EQ(face_list(obj).size(), 3732u);
  EXPECT_EQ(face_list(stl).size(), 3732u);
  EXPECT_EQ(face_list(off).size(), 3732u);
  // Every format writes back to the same vertices and faces.
  FormatDir dir;
  for (const char* ext : {".obj", ".off", ".ply", ".stl"}) {
    WriteOptions ascii;
    ascii.encoding = PlyEncoding::Ascii;
    write_point_cloud(dir.file(std::string("w") + ext), obj, ascii);
    const PointCloud back = read_point_cloud(dir.file(std::string("w") + ext));
    EXPECT_EQ(back.positions, obj.positions) << ext;
    EXPECT_EQ(polygons(back), polygons(obj)) << ext;
  }
}

}  // namespace
}  // namespace detexture
