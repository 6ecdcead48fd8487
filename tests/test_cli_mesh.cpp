// Textured meshes through the command line: a plane with bumps, triangulated,
// in every mesh format. It must come out in the same format with the same
// faces, the bumps lowered, no triangle flipped and no new fold.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_fixture.h"
#include "detexture/geometry/face_normals.h"
#include "detexture/geometry/mesh_folds.h"
#include "detexture/io/face_list.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "detexture/pipeline/remove_texture.h"

namespace fs = std::filesystem;

namespace detexture {
namespace {

// A 41 x 41 grid of the unit square with four bumps of height 0.02 and
// width 0.03 (r = 0.06 covers them), two triangles per cell.
PointCloud bumpy_mesh() {
  const int side = 41;
  PointCloud c;
  c.positions.resize(side * side, 3);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const double x = a / (side - 1.0), y = b / (side - 1.0);
      double z = 0.0;
      for (const double cx : {0.3, 0.7})
        for (const double cy : {0.3, 0.7}) {
          const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
          z += 0.02 * std::exp(-d2 / (2 * 0.03 * 0.03));
        }
      c.positions.row(a * side + b) << x, y, z;
    }
  FaceList faces;
  for (int a = 0; a + 1 < side; ++a)
    for (int b = 0; b + 1 < side; ++b) {
      const std::uint32_t v = a * side + b;
      const std::uint32_t t1[3] = {v, v + side, v + side + 1}, t2[3] = {v, v + side + 1, v + 1};
      faces.add(t1, 3);
      faces.add(t2, 3);
    }
  set_face_list(c, faces);
  return c;
}

class CliMesh : public test::CliFixture {
 protected:
  CliMesh() : CliFixture("detexture_cli_mesh_") {}
};

TEST_F(CliMesh, EveryMeshFormatComesOutTheSameWithTheBumpsLowered) {
  const PointCloud mesh = bumpy_mesh();
  for (const char* ext : {".ply", ".obj", ".off", ".stl"}) {
    WriteOptions ascii;
    ascii.encoding = PlyEncoding::Ascii;  // STL ascii keeps the doubles exactly
    const std::string in = path(std::string("in") + ext), out = path(std::string("out") + ext);
    write_point_cloud(in, mesh, ascii);
    // STL has no vertex list: its vertices are numbered as the triangles
    // first use them, so the faces are compared with the file's own.
    const PointCloud input = read_point_cloud(in);
    const FaceList faces = face_list(input);
    const TriangleIndices T = triangulate_faces(faces);
    const MeshFolds before = measure_folds(input.positions, T, input.positions);
    ASSERT_EQ(
        run(in + " -o " + out + " -r 0.06 --encoding ascii --stats " + path("s.json") + " -f"), 0)
        << ext << ": " << stderr_;
    EXPECT_NE(stderr_.find("normals from the faces"), std::string::npos) << ext << stderr_;
    EXPECT_NE(stderr_.find("(no normals: taking them from the faces)"), std::string::npos)
        << ext << stderr_;
    EXPECT_NE(stderr_.find("flipped triangles: 0 (0.00%)"), std::string::npos) << stderr_;
    const PointCloud result = read_point_cloud(out);
    ASSERT_EQ(result.size(), mesh.size()) << ext;
    const FaceList out_faces = face_list(result);
    EXPECT_EQ(out_faces.indices, faces.indices) << ext;
    EXPECT_EQ(out_faces.offsets, faces.offsets) << ext;
    const MeshFolds after = measure_folds(result.positions, T, input.positions);
    EXPECT_EQ(after.flipped, 0u) << ext;
    EXPECT_LE(after.folded, before.folded) << ext;
    // The bumps' peaks (0.02 high) come down by more than half.
    EXPECT_LT(result.positions.col(2).maxCoeff(), 0.01) << ext;
    std::ifstream stats(path("s.json"));
    std::stringstream json;
    json << stats.rdbuf();
    EXPECT_NE(json.str().find("\"output\": {\"folded_edges\": "), std::string::npos) << json.str();
  }
}

TEST_F(CliMesh, ThePaperModeTreatsTheVerticesAsACloudAndReportsItsFolds) {
  const PointCloud mesh = bumpy_mesh();
  write_point_cloud(path("in.ply"), mesh);
  ASSERT_EQ(run(path("in.ply") + " -o " + path("out.ply") + " -r 0.06 --mesh cloud"), 0) << stderr_;
  EXPECT_EQ(stderr_.find("normals from the faces"), std::string::npos) << stderr_;
  EXPECT_NE(stderr_.find("(no normals: estimating them)"), std::string::npos) << stderr_;
  EXPECT_NE(stderr_.find("edges folded past 60°"), std::string::npos) << stderr_;
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out2.ply") + " --mesh nonsense"), 2);
  // A path limit below r would cut even the nearest rim of every R_i.
  EXPECT_EQ(run(path("in.ply") + " -o " + path("out2.ply") + " -r 0.06 --mesh-path-limit 0.5"), 2);
  EXPECT_NE(stderr_.find("mesh path limit"), std::string::npos) << stderr_;
}

TEST(RemoveTextureMesh, FacesGiveTheNormalsAndBoundTheUpdate) {
  const PointCloud mesh = bumpy_mesh();
  RemoveTextureParams params;
  params.radius = {0.06, Length::Unit::Absolute};
  const RemoveTextureResult r = remove_texture(mesh.positions, Normals(), face_list(mesh), params);
  EXPECT_TRUE(r.report.mesh);
  EXPECT_TRUE(r.report.normals_from_faces);
  EXPECT_FALSE(r.report.normals_estimated) << "no PCA";
  EXPECT_EQ(r.report.triangles, 3200u);
  EXPECT_EQ(r.report.folds.output.flipped, 0u);
  EXPECT_LE(r.report.folds.output.folded, r.report.folds.input.folded);
  EXPECT_LE(r.report.folds.output.p99_dihedral_deg,
            std::max(r.report.folds.input.p99_dihedral_deg, 20.0) + 1e-9);
  // The input normals are the faces' (up, on this height field).
  for (Eigen::Index i = 0; i < r.input_normals.rows(); ++i)
    ASSERT_GT(r.input_normals(i, 2), 0.9) << i;
}

// Two sheets 0.03 apart, both facing up, closer than r: the bumpy grid above
// a flat copy of it. Along the mesh they never meet, so the flat sheet's
// neighborhoods hold only itself and it stays exactly where it is; with
// Euclidean R_i (path limit 0) the bumps above reach it and move it.
TEST(RemoveTextureMesh, NeighborhoodsFollowTheMeshNotTheNextSheet) {
  const PointCloud top = bumpy_mesh();
  const Eigen::Index n = top.positions.rows();
  Positions P(2 * n, 3);
  P.topRows(n) = top.positions;
  P.bottomRows(n) = top.positions;
  P.bottomRows(n).col(2).setConstant(-0.03);
  const FaceList one = face_list(top);
  FaceList both;
  for (int copy = 0; copy < 2; ++copy)
    for (std::size_t f = 0; f < one.size(); ++f) {
      std::uint32_t t[3];
      for (int k = 0; k < 3; ++k)
        t[k] = one.indices[one.offsets[f] + k] + static_cast<std::uint32_t>(copy * n);
      both.add(t, 3);
    }
  RemoveTextureParams params;
  params.radius = {0.06, Length::Unit::Absolute};
  const auto lowest_move = [&](const RemoveTextureResult& r) {
    double most = 0.0;
    for (Eigen::Index i = n; i < 2 * n; ++i)
      most = std::max(most, std::abs(r.positions(i, 2) + 0.03));
    return most;
  };
  const RemoveTextureResult along = remove_texture(P, Normals(), both, params);
  EXPECT_EQ(along.report.mesh_path_points, static_cast<std::size_t>(2 * n));
  EXPECT_LT(lowest_move(along), 1e-12);
  params.mesh_paths.path_factor = 0.0;
  const RemoveTextureResult euclidean = remove_texture(P, Normals(), both, params);
  EXPECT_EQ(euclidean.report.mesh_path_points, 0u);
  EXPECT_GT(lowest_move(euclidean), 1e-3);
  // The paper's mode treats the vertices as a cloud: no path limit.
  params.mesh_paths.path_factor = 1.0;
  params.use_faces = false;
  EXPECT_EQ(remove_texture(P, Normals(), both, params).report.mesh_path_points, 0u);
}

}  // namespace
}  // namespace detexture
