#include "detexture/pipeline/detect_texture.h"

#include <gtest/gtest.h>
#include <omp.h>

#include "detexture/eval/synthesize_shape.h"
#include "test_support.h"

namespace detexture {
namespace {

// A bump of width 0.015 (visible out to ~0.05) on a plane sampled every 0.01;
// neighborhoods of radius 0.06 always hold plenty of flat plane, so RANSAC
// finds the plane and the bump's points are its outliers.
TEST(DetectTexture, BumpOnPlaneIsTexture) {
  const auto s = test::bumpy_plane(101, 0.03, 0.015);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.06, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  const TextureDetection det = detect_texture(s.P, R, params);
  for (int i = 0; i < s.P.rows(); ++i) {
    const double dist = std::hypot(s.P(i, 0) - 0.5, s.P(i, 1) - 0.5);
    if (s.height(i) > 2 * params.lambda) EXPECT_TRUE(det.is_texture[i]) << "point " << i;
    if (dist > 0.06 + 0.05) EXPECT_FALSE(det.is_texture[i]) << "point " << i;
  }
  EXPECT_GT(det.texture_points, 20u);
  EXPECT_EQ(det.no_plane, 0u);
}

// synth's sphere of radius 0.5, exact normals included.
SynthesizedShape sphere(TextureKind texture, std::int64_t points) {
  SynthParams sp;
  sp.shape = BaseShape::Sphere;
  sp.texture = texture;
  sp.size = 0.1;
  sp.amplitude = 0.03;
  sp.points = points;
  sp.ground_truth_points = 1;
  return synthesize_shape(sp);
}

// A sphere of radius 0.5 seen through neighborhoods of r = 0.15: the sag
// r²/(2·0.5) = 0.0225 is three times λ = 0.0075, so a plane holds at most a
// band 2λ deep, 4·0.5·λ/r² = 2/3 of the area of R_i, and every point fits
// in fewer than δ = 0.8 of its neighborhoods. The quadric holds it all.
TEST(DetectTexture, CurvedSurfaceIsNotTextureWithTheQuadric) {
  const SynthesizedShape s = sphere(TextureKind::None, 8000);
  const Neighborhoods R = radius_neighborhoods(s.positions, {0.15, 0});
  DetectTextureParams params;
  params.lambda = 0.0075;
  params.surface = UnderlyingSurface::Plane;
  const TextureDetection plane = detect_texture(s.positions, R, params);
  EXPECT_GT(plane.texture_points, s.positions.rows() / 2);
  params.surface = UnderlyingSurface::Quadric;
  params.min_surface_radius = 0.075;
  const TextureDetection quadric = detect_texture(s.positions, R, params);
  EXPECT_LT(quadric.texture_points, s.positions.rows() / 100);
  // A limit on the curvature tighter than the sphere's gives the plane back.
  params.min_surface_radius = 1.0;
  EXPECT_EQ(detect_texture(s.positions, R, params).is_texture, plane.is_texture);
}

// Bumps on that sphere (R = 0.1, A = 0.03) stay texture: the quadric is
// fitted to the plane's inliers, so the bumps do not bend it; with the
// normals (as remove_texture calls it) as without.
TEST(DetectTexture, BumpsOnACurvedSurfaceStayTexture) {
  const SynthesizedShape s = sphere(TextureKind::Bumps, 12000);
  const double amplitude = 0.03;
  const Neighborhoods R = radius_neighborhoods(s.positions, {0.15, 0});
  DetectTextureParams params;
  params.lambda = 0.0075;
  params.min_surface_radius = 0.075;
  for (const bool with_normals : {false, true}) {
    const TextureDetection det = with_normals ? detect_texture(s.positions, s.normals, R, params)
                                              : detect_texture(s.positions, R, params);
    std::size_t high = 0, high_found = 0, flat = 0, flat_found = 0;
    for (std::size_t i = 0; i < s.texture_heights.size(); ++i) {
      if (s.texture_heights[i] > 0.5 * amplitude) {
        ++high;
        high_found += det.is_texture[i];
      } else if (s.texture_heights[i] == 0.0) {
        ++flat;
        flat_found += det.is_texture[i];
      }
    }
    ASSERT_GT(high, 100u);
    EXPECT_GT(high_found, 0.95 * high);
    EXPECT_LT(flat_found, 0.2 * flat);
  }
}

TEST(DetectTexture, FlatPlaneHasNoTexture) {
  const auto s = test::bumpy_plane(41, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 1e-6;
  const TextureDetection det = detect_texture(s.P, R, params);
  EXPECT_EQ(det.texture_points, 0u);
  // One good try suffices when every point is an inlier (grid-aligned triples
  // are collinear and cost a retry now and then).
  EXPECT_LT(det.mean_iterations, 1.5);
}

TEST(DetectTexture, InlierCountsFollowEq2) {
  const auto s = test::bumpy_plane(61, 0.03, 0.02);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  params.delta = 0.7;
  const TextureDetection det = detect_texture(s.P, R, params);
  for (int i = 0; i < s.P.rows(); ++i) {
    EXPECT_EQ(det.members[i], R.count(i)) << "radius neighborhoods are symmetric";
    EXPECT_LE(det.inliers[i], det.members[i]);
    EXPECT_EQ(det.is_texture[i] != 0, !(det.inliers[i] > params.delta * det.members[i]));
  }
}

// Symmetric neighborhoods gather T_j and N_j over R_j; others scatter from
// every R_i. Both must count the same pairs, planes at creases included.
TEST(DetectTexture, GatherAndScatterCountTheSame) {
  const auto s = test::bumpy_plane(81, 0.03, 0.02);
  Positions P = s.P;
  for (int i = 0; i < P.rows(); ++i)  // fold the sheet into a crease along x = 0.5
    if (P(i, 0) > 0.5) P(i, 2) += 0.6 * (P(i, 0) - 0.5);
  Neighborhoods R = radius_neighborhoods(P, {0.07, 0});
  ASSERT_TRUE(R.symmetric);
  DetectTextureParams params;
  params.lambda = 0.002;
  const TextureDetection gathered = detect_texture(P, R, params);
  R.symmetric = false;
  const TextureDetection scattered = detect_texture(P, R, params);
  EXPECT_EQ(gathered.inliers, scattered.inliers);
  EXPECT_EQ(gathered.members, scattered.members);
  EXPECT_EQ(gathered.is_texture, scattered.is_texture);
  EXPECT_GT(gathered.texture_points, 20u);
  // A cap that cuts rows makes the neighborhoods one-sided.
  EXPECT_FALSE(radius_neighborhoods(P, {0.07, 10}).symmetric);
  EXPECT_TRUE(radius_neighborhoods(P, {0.07, 100000}).symmetric);
}

TEST(DetectTexture, IdenticalForAnyThreadCount) {
  const auto s = test::bumpy_plane(81, 0.03, 0.03);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.05, 0});
  DetectTextureParams params;
  params.lambda = 0.003;
  omp_set_num_threads(1);
  const TextureDetection a = detect_texture(s.P, R, params);
  omp_set_num_threads(2);
  const TextureDetection b = detect_texture(s.P, R, params);
  EXPECT_EQ(a.inliers, b.inliers);
  EXPECT_EQ(a.is_texture, b.is_texture);
  params.seed = 2;
  const TextureDetection c = detect_texture(s.P, R, params);
  EXPECT_EQ(c.members, a.members);
}

TEST(DetectTexture, TooFewNeighborsCountedNotFatal) {
  Positions P(2, 3);
  P << 0, 0, 0, 1, 0, 0;
  const Neighborhoods R = radius_neighborhoods(P, {0.1, 0});
  DetectTextureParams params;
  params.lambda = 0.01;
  const TextureDetection det = detect_texture(P, R, params);
  EXPECT_EQ(det.no_plane, 2u);
  EXPECT_EQ(det.texture_points, 0u);
}

// The vote's normal test: a flat sheet whose normals are tilted by 40° in a
// disc of radius 0.1 (relief too low to leave the plane, as midway up a wave,
// but tilted with it). By positions alone every point fits; with
// vote_normal_angle_deg = 30 the tilted points never vote surface, and the
// upright ones away from the disc still do. Gathered and scattered counts agree.
TEST(DetectTexture, VoteNormalAngleRejectsTiltedInliers) {
  const auto s = test::bumpy_plane(61, 0.0, 0.1);
  Normals N(s.P.rows(), 3);
  const double tilt = 40.0 * M_PI / 180.0;
  auto in_disc = [&](int i) { return std::hypot(s.P(i, 0) - 0.5, s.P(i, 1) - 0.5) < 0.1; };
  for (int i = 0; i < s.P.rows(); ++i) {
    if (in_disc(i))
      N.row(i) << std::sin(tilt), 0.0, std::cos(tilt);
    else
      N.row(i) << 0.0, 0.0, 1.0;
  }
  Neighborhoods R = radius_neighborhoods(s.P, {0.06, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  const TextureDetection positions_only = detect_texture(s.P, N, R, params);
  EXPECT_EQ(positions_only.texture_points, 0u);
  params.vote_normal_angle_deg = 30.0;
  const TextureDetection voted = detect_texture(s.P, N, R, params);
  for (int i = 0; i < s.P.rows(); ++i) {
    if (in_disc(i)) EXPECT_TRUE(voted.is_texture[i]) << "point " << i;
    if (!in_disc(i)) EXPECT_FALSE(voted.is_texture[i]) << "point " << i;
  }
  R.symmetric = false;
  EXPECT_EQ(detect_texture(s.P, N, R, params).inliers, voted.inliers);
  params.vote_normal_angle_deg = 50.0;  // wider than the tilt: all fit again
  EXPECT_EQ(detect_texture(s.P, N, R, params).texture_points, 0u);
}

TEST(DetectTexture, RejectsBadParameters) {
  const auto s = test::bumpy_plane(5, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.5, 0});
  DetectTextureParams params;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument) << "lambda unset";
  params.lambda = 0.01;
  params.delta = 1.0;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
  params.delta = 0.8;
  params.max_iterations = 0;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
  params.max_iterations = 100;
  params.soft_floor = 0.8;  // must stay below delta
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
  params.soft_floor = -0.1;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
  params.soft_floor = 0.3;
  params.vote_normal_angle_deg = 0.0;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
  params.vote_normal_angle_deg = 181.0;
  EXPECT_THROW(detect_texture(s.P, R, params), std::invalid_argument);
}

// Ω weights: hard is 1 - label; soft ramps from 0 at soft_floor to 1 at δ in
// the vote share T/N, and the labels (Eq. 2) do not change.
TEST(DetectTexture, OmegaWeightsFollowTheVotes) {
  auto s = test::bumpy_plane(61, 0.03, 0.02);
  for (int i = 0; i < s.P.rows(); ++i)  // a ripple, so that some votes fall in between
    s.P(i, 2) += 0.002 * std::sin(40.0 * s.P(i, 0));
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  params.subneighborhood = SubneighborhoodMode::Hard;
  const TextureDetection hard = detect_texture(s.P, R, params);
  EXPECT_EQ(hard.omega, hard_omega(hard.is_texture));
  params.subneighborhood = SubneighborhoodMode::Soft;
  params.soft_floor = 0.3;
  const TextureDetection soft = detect_texture(s.P, R, params);
  EXPECT_EQ(soft.is_texture, hard.is_texture);
  std::size_t partial = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double share = static_cast<double>(soft.inliers[i]) / soft.members[i];
    const double expect = std::clamp((share - 0.3) / (0.8 - 0.3), 0.0, 1.0);
    EXPECT_NEAR(soft.omega[i], expect, 1e-6) << "point " << i;
    partial += soft.omega[i] > 0.0f && soft.omega[i] < 1.0f;
  }
  EXPECT_GT(partial, 0u) << "the bump's flank has votes in between";
}

}  // namespace
}  // namespace detexture

namespace detexture {
namespace {

// Eq. 2 with one plane per neighborhood marks a band along a sharp crease as
// texture; with the second plane (our default) the crease is surface.
TEST(DetectTexture, CreaseIsSurfaceWithSecondPlane) {
  const auto s = test::folded_plane(61, 90.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  params.planes = 1;
  const TextureDetection one = detect_texture(s.P, R, params);
  params.planes = 2;
  const TextureDetection two = detect_texture(s.P, R, params);
  std::size_t near_crease = 0, band_one = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double d = (s.P.row(i) - Eigen::RowVector3d(0.5, s.P(i, 1), 0.0)).norm();
    if (d < 0.03) {
      ++near_crease;
      band_one += one.is_texture[i];
    }
  }
  EXPECT_GT(band_one, near_crease / 2) << "the paper's rule loses the crease to texture";
  EXPECT_EQ(two.texture_points, 0u);
}

// A raised plateau parallel to the plane is texture even with two planes:
// the second plane must meet the first at an angle.
TEST(DetectTexture, ParallelTerraceStaysTexture) {
  auto s = test::bumpy_plane(81, 0.0, 0.1);
  for (int i = 0; i < s.P.rows(); ++i)
    if (std::hypot(s.P(i, 0) - 0.5, s.P(i, 1) - 0.5) < 0.04) s.P(i, 2) = 0.02;
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  const TextureDetection det = detect_texture(s.P, R, params);
  for (int i = 0; i < s.P.rows(); ++i)
    if (s.P(i, 2) > 0.01) EXPECT_TRUE(det.is_texture[i]) << "point " << i;
}

}  // namespace
}  // namespace detexture

namespace detexture {
namespace {

// Three faces meeting at a corner of a box: with three planes per
// neighborhood nothing is texture; with two, points near the corner are.
TEST(DetectTexture, CornerIsSurfaceWithThreePlanes) {
  const int side = 40;
  Positions P(3 * side * side, 3);
  int i = 0;
  for (int face = 0; face < 3; ++face)
    for (int a = 0; a < side; ++a)
      for (int b = 0; b < side; ++b) {
        Eigen::RowVector3d q;
        q(face) = 0.0;
        q((face + 1) % 3) = (a + 0.5) / side;
        q((face + 2) % 3) = (b + 0.5) / side;
        P.row(i++) = q;
      }
  const Neighborhoods R = radius_neighborhoods(P, {0.12, 0});
  DetectTextureParams params;
  params.lambda = 0.002;
  params.planes = 2;
  const TextureDetection two = detect_texture(P, R, params);
  params.planes = 3;
  const TextureDetection three = detect_texture(P, R, params);
  EXPECT_GT(two.texture_points, 10u);
  EXPECT_EQ(three.texture_points, 0u);
}

}  // namespace
}  // namespace detexture
