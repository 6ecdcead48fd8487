#include "detexture/pipeline/drop_neighbors_across_surfaces.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <stdexcept>

#include "detexture/pipeline/detect_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

// Four points, all neighbors of each other, with normals and labels set by
// hand: which pairs stay follows from the angles alone.
struct Four {
  Positions P = Positions::Zero(4, 3);
  Normals N = Normals::Zero(4, 3);
  Normals S = Normals::Zero(4, 3);  // surface normals
  std::vector<std::uint8_t> tex = std::vector<std::uint8_t>(4, 0);
};

Neighborhoods everyone(const Positions& P) { return radius_neighborhoods(P, {10.0, 0}); }

bool has(const Neighborhoods& R, std::size_t i, std::uint32_t j) {
  for (const std::uint32_t* k = R.begin(i); k != R.end(i); ++k)
    if (*k == j) return true;
  return false;
}

Eigen::RowVector3d tilted(double deg) {
  const double t = deg * M_PI / 180.0;
  return {std::sin(t), 0.0, std::cos(t)};
}

// 0: a face point (normal up). 1: the steep flank of a bump on that face
// (normal 80° off, texture, its surface normal up). 2: a point past a tip
// (normal 90° off, surface). 3: texture on the far side of a thin part
// (normal 170° off, its surface normal down).
Four tip_and_bump() {
  Four f;
  for (int i = 0; i < 4; ++i) f.P.row(i) << 0.01 * i, 0.0, 0.0;
  f.N.row(0) = tilted(0);
  f.S.row(0) = tilted(0);
  f.N.row(1) = tilted(80);
  f.S.row(1) = tilted(0);
  f.tex[1] = 1;
  f.N.row(2) = tilted(90);
  f.S.row(2) = tilted(90);
  f.N.row(3) = tilted(170);
  f.S.row(3) = tilted(180);
  f.tex[3] = 1;
  return f;
}

TEST(DropNeighborsAcrossSurfaces, KeepsTheFlankOfABumpAndPartsATip) {
  const Four f = tip_and_bump();
  Neighborhoods R = everyone(f.P);
  const std::size_t removed = drop_neighbors_across_surfaces(R, f.N, f.S, f.tex, {});
  // The flank's surface is the face: 0-1 stay although their normals are 80° apart.
  EXPECT_TRUE(has(R, 0, 1) && has(R, 1, 0));
  // Past the tip: 90° from the face. The flank's surface is 90° from the
  // tip point too, but the tip point's own normal is 10° from the flank's,
  // so that pair stays: one side accepting is enough.
  EXPECT_FALSE(has(R, 0, 2) || has(R, 2, 0));
  EXPECT_TRUE(has(R, 1, 2) && has(R, 2, 1));
  // The far side of the thin part is 170-180° from everything on this side
  // and 80° from the tip point.
  for (std::uint32_t j : {0u, 1u, 2u}) EXPECT_FALSE(has(R, 3, j) || has(R, j, 3)) << j;
  // Every point keeps itself, also the flank 80° from its own surface.
  for (std::size_t i = 0; i < 4; ++i) EXPECT_TRUE(has(R, i, static_cast<std::uint32_t>(i)));
  EXPECT_EQ(removed, 8u);  // four pairs, both ways
  for (std::size_t i = 0; i < 4; ++i)
    for (std::uint32_t j = 0; j < 4; ++j)
      EXPECT_EQ(has(R, i, j), has(R, j, static_cast<std::uint32_t>(i))) << i << ", " << j;
}

TEST(DropNeighborsAcrossSurfaces, AngleOf180KeepsAllAndWiderAnglesKeepMore) {
  const Four f = tip_and_bump();
  Neighborhoods all = everyone(f.P);
  const Neighborhoods before = all;
  EXPECT_EQ(drop_neighbors_across_surfaces(all, f.N, f.S, f.tex, {180.0}), 0u);
  EXPECT_EQ(all.indices, before.indices);
  // At 95° the tip point (90°) stays with the face and the flank; the far
  // side is still more than 95° from all but the tip (80°).
  Neighborhoods wide = everyone(f.P);
  EXPECT_EQ(drop_neighbors_across_surfaces(wide, f.N, f.S, f.tex, {95.0}), 4u);
  EXPECT_TRUE(has(wide, 0, 2) && has(wide, 1, 2) && has(wide, 2, 3));
}

TEST(DropNeighborsAcrossSurfaces, ZeroNormalsAreKept) {
  Four f = tip_and_bump();
  f.S.row(1).setZero();  // no surface was fitted under the flank point
  f.N.row(2).setZero();  // no normal at the tip point
  Neighborhoods R = everyone(f.P);
  drop_neighbors_across_surfaces(R, f.N, f.S, f.tex, {});
  EXPECT_TRUE(has(R, 1, 2) && has(R, 0, 2) && has(R, 2, 3));
  // 1 judges nothing, but 3's surface (down) is 100° from 1's normal and
  // 1 has no reference: the pair stays.
  EXPECT_TRUE(has(R, 1, 3));
  EXPECT_FALSE(has(R, 0, 3));
  // A texture point without a normal of its own (but with a surface under
  // it) is judged by nobody: every pair with it stays.
  Four g = tip_and_bump();
  g.N.row(3).setZero();
  Neighborhoods S = everyone(g.P);
  drop_neighbors_across_surfaces(S, g.N, g.S, g.tex, {});
  for (std::uint32_t j : {0u, 1u, 2u}) EXPECT_TRUE(has(S, 3, j) && has(S, j, 3)) << j;
}

TEST(DropNeighborsAcrossSurfaces, RejectsBadInput) {
  const Four f = tip_and_bump();
  Neighborhoods R = everyone(f.P);
  EXPECT_THROW(drop_neighbors_across_surfaces(R, f.N, f.S, f.tex, {0.0}), std::invalid_argument);
  EXPECT_THROW(drop_neighbors_across_surfaces(R, f.N, f.S, f.tex, {181.0}), std::invalid_argument);
  EXPECT_THROW(drop_neighbors_across_surfaces(R, f.N, Normals(3, 3), f.tex, {}),
               std::invalid_argument);
  EXPECT_THROW(drop_neighbors_across_surfaces(R, f.N, f.S, {0, 1}, {}), std::invalid_argument);
}

// detect_texture's surface normal is the face under a bump, not the bump's
// flank, and follows the sign of the point normals.
TEST(DropNeighborsAcrossSurfaces, SurfaceNormalsOfABumpAreTheFaceUnderIt) {
  auto s = test::bumpy_plane(101, 0.03, 0.015);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.06, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  EXPECT_EQ(detect_texture(s.P, s.N, R, params).surface_normal.rows(), 0);
  params.surface_normals = true;
  for (const double sign : {1.0, -1.0}) {
    const Normals N = sign * s.N;
    const TextureDetection det = detect_texture(s.P, N, R, params);
    ASSERT_EQ(det.surface_normal.rows(), s.P.rows());
    std::size_t steep = 0;
    for (Eigen::Index i = 0; i < s.P.rows(); ++i) {
      if (!det.is_texture[static_cast<std::size_t>(i)]) continue;
      const double flank = test::angle_deg(N.row(i), Eigen::RowVector3d(0, 0, sign));
      steep += flank > 30.0;
      EXPECT_LT(test::angle_deg(det.surface_normal.row(i), Eigen::RowVector3d(0, 0, sign)), 3.0)
          << "point " << i << ", flank at " << flank << "°";
    }
    EXPECT_GT(steep, 10u) << "the bump must have steep flanks for the test to mean anything";
  }
}

// A point on a flank turned past 90° (an overhang: its normal 100° from the
// face's) still has the face, signed up, as its surface: its own normal is
// within 30° of the face's plane, so the face's points decide the sign.
TEST(DropNeighborsAcrossSurfaces, SurfaceUnderAnOverhangIsSignedByTheFace) {
  auto s = test::bumpy_plane(41, 0.0, 1.0);
  const Eigen::Index p = 20 * 41 + 20;  // the middle
  const double t = 100.0 * M_PI / 180.0;
  s.N.row(p) << std::sin(t), 0.0, std::cos(t);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  params.surface_normals = true;
  const TextureDetection det = detect_texture(s.P, s.N, R, params);
  EXPECT_LT(test::angle_deg(det.surface_normal.row(p), Eigen::RowVector3d(0, 0, 1)), 1.0);
}

// On a curved base seen from one side only (R_i a half disk), the plane
// fitted to R_i leans towards the half's middle; the quadric's slope at
// p_i (e, f) turns the surface normal back to the sphere's radial normal.
TEST(DropNeighborsAcrossSurfaces, SurfaceNormalsFollowACurvedBaseSeenFromOneSide) {
  const auto s = test::fibonacci_sphere(8000, 1.0);
  Neighborhoods R = radius_neighborhoods(s.P, {0.3, 0});
  keep_neighbors(R, [&](std::size_t i, std::uint32_t j) {
    const Eigen::RowVector3d side = Eigen::RowVector3d(0, 0, 1).cross(s.N.row(i));
    return j == i || (s.P.row(j) - s.P.row(i)).dot(side) >= 0.0;
  });
  R.symmetric = false;
  DetectTextureParams params;
  params.lambda = 0.005;
  params.surface_normals = true;
  params.min_surface_radius = 0.5;
  double quadric_worst = 0.0, plane_mean = 0.0;
  std::size_t counted = 0;
  const TextureDetection quadric = detect_texture(s.P, s.N, R, params);
  params.surface = UnderlyingSurface::Plane;
  const TextureDetection plane = detect_texture(s.P, s.N, R, params);
  for (Eigen::Index i = 0; i < s.P.rows(); i += 20) {
    if (std::abs(s.N(i, 2)) > 0.8) continue;  // near the poles "side" degenerates
    quadric_worst =
        std::max(quadric_worst, test::angle_deg(quadric.surface_normal.row(i), s.N.row(i)));
    plane_mean += test::angle_deg(plane.surface_normal.row(i), s.N.row(i));
    ++counted;
  }
  ASSERT_GT(counted, 100u);
  EXPECT_LT(quadric_worst, 1.5);
  EXPECT_GT(plane_mean / counted, 4.0);
}

}  // namespace
}  // namespace detexture
