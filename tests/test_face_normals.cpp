// Vertex normals from faces, the orientation of the faces, and the fold
// measures: on a cube and on two triangles, whose answers are known by hand.
#include "detexture/geometry/face_normals.h"

#include <gtest/gtest.h>

#include <cmath>

#include "detexture/geometry/mesh_folds.h"

namespace detexture {
namespace {

// The cube [0,1]^3: 8 corners, 6 quads wound outwards.
struct Cube {
  Positions P;
  FaceList faces;
};
Cube cube() {
  Cube c;
  c.P.resize(8, 3);
  for (int i = 0; i < 8; ++i) c.P.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) c.faces.add(q, 4);
  return c;
}

TEST(FaceNormals, CubeCornersGetTheDiagonalWhateverTheSplit) {
  const Cube c = cube();
  TriangleIndices T = triangulate_faces(c.faces);
  ASSERT_EQ(T.rows(), 12);
  EXPECT_EQ(orient_triangles(c.P, T), 0u) << "already consistent and outward";
  // Angle weights: each corner sees 90° of each of its three faces, whether
  // the fan gives it one triangle or two, so the normal is the diagonal.
  std::size_t isolated = 7;
  const Normals N = face_normals(c.P, T, {}, &isolated);
  EXPECT_EQ(isolated, 0u);
  for (int i = 0; i < 8; ++i) {
    const Eigen::RowVector3d outward =
        (c.P.row(i) - Eigen::RowVector3d(0.5, 0.5, 0.5)).normalized();
    EXPECT_NEAR((N.row(i) - outward).norm(), 0.0, 1e-12) << i;
  }
  // Area weights depend on the split: corner 1 is in both triangles of one
  // face's fan but in one triangle of the two others, so it leans off the
  // diagonal towards (1, 0, 0) by weights 1, 1/2, 1/2.
  const Normals A = face_normals(c.P, T, {FaceWeighting::Area});
  EXPECT_NEAR((A.row(1) - Eigen::RowVector3d(2, -1, -1).normalized()).norm(), 0.0, 1e-12);
}

TEST(FaceNormals, OrientationIsMadeConsistentAndOutward) {
  const Cube c = cube();
  TriangleIndices good = triangulate_faces(c.faces);
  orient_triangles(c.P, good);
  // Turn three triangles around, and then the whole cube inside out.
  TriangleIndices T = good;
  for (int t : {1, 4, 9}) std::swap(T(t, 1), T(t, 2));
  EXPECT_EQ(orient_triangles(c.P, T), 3u);
  EXPECT_EQ(T, good);
  for (Eigen::Index t = 0; t < T.rows(); ++t) std::swap(T(t, 1), T(t, 2));
  EXPECT_EQ(orient_triangles(c.P, T), 12u);
  EXPECT_EQ(T, good);
  // A vertex in no triangle is counted and left zero.
  Positions P(9, 3);
  P << c.P, Eigen::RowVector3d(5, 5, 5);
  std::size_t isolated = 0;
  const Normals N = face_normals(P, T, {}, &isolated);
  EXPECT_EQ(isolated, 1u);
  EXPECT_EQ(N.row(8), Eigen::RowVector3d::Zero());
}

TEST(MeshFolds, TwoTrianglesFoldedByAKnownAngle) {
  // A hinge along the x axis: one triangle in z = 0, the other lifted by 70°.
  const double a = 70.0 * M_PI / 180.0;
  Positions P(4, 3);
  P << 0, 0, 0, 1, 0, 0, 0.5, -1, 0, 0.5, std::cos(a), std::sin(a);
  TriangleIndices T(2, 3);
  T << 0, 2, 1, 0, 1, 3;
  const InteriorEdges edges = interior_edges(T);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_NEAR(dihedral_angles_deg(P, T, edges)[0], 70.0, 1e-9);
  MeshFolds m = measure_folds(P, T, P, 60.0);
  EXPECT_EQ(m.edges, 1u);
  EXPECT_EQ(m.folded, 1u);
  EXPECT_EQ(m.flipped, 0u);
  // Bending the tip below the plane turns its normal by less than 90°; laying
  // it over the first triangle turns it by more: flipped.
  Positions Q = P;
  Q.row(3) << 0.5, 1, -0.3;
  m = measure_folds(Q, T, P, 60.0);
  EXPECT_EQ(m.flipped, 0u) << "the normal turned by less than 90°";
  Q.row(3) << 0.5, -0.5, 0.1;  // over the first triangle: folded flat onto it
  m = measure_folds(Q, T, P, 60.0);
  EXPECT_EQ(m.flipped, 1u);
  EXPECT_EQ(m.folded, 1u);
}

}  // namespace
}  // namespace detexture
