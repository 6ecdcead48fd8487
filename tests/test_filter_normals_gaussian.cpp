#include "detexture/pipeline/filter_normals_gaussian.h"

#include <gtest/gtest.h>

#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/detect_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

double max_angle_to_z(const Normals& N) {
  double worst = 0.0;
  for (int i = 0; i < N.rows(); ++i)
    worst = std::max(worst, test::angle_deg(N.row(i), Eigen::RowVector3d(0, 0, 1)));
  return worst;
}

// Fig. 4: with the sub-neighborhood only the plane's normals (+z) are
// averaged, so the bump disappears from the normals; the plain Gaussian
// averages the bump's tilted normals and leaves a dent in the field.
TEST(FilterNormalsGaussian, SubNeighborhoodRemovesBumpFromNormals) {
  const auto s = test::bumpy_plane(101, 0.03, 0.015);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.06, 0});
  DetectTextureParams tp;
  tp.lambda = 0.002;
  const TextureDetection det = detect_texture(s.P, R, tp);
  FilterNormalsGaussianParams gp;
  gp.sigma_s = 0.06;
  const GaussianFilterResult sub = filter_normals_gaussian(s.P, s.N, R, det.omega, gp);
  gp.use_subneighborhood = false;
  const GaussianFilterResult plain = filter_normals_gaussian(s.P, s.N, R, {}, gp);
  EXPECT_EQ(sub.empty_subneighborhoods, 0u);
  EXPECT_LT(max_angle_to_z(sub.normals), 3.0);
  EXPECT_GT(max_angle_to_z(plain.normals), 2.0 * max_angle_to_z(sub.normals));
  EXPECT_GT(max_angle_to_z(s.N), 30.0) << "the bump is steep in the input";
}

// Dense texture: scales cover the whole plane, so no point is plainly
// "surface"; Eq. 2's votes spread between 0 and 1 and the hard labels keep a
// biased subset of each scale, whose normals average to a tilt. The soft
// weights keep most points at partial weight and the tilts cancel.
TEST(FilterNormalsGaussian, SoftSubNeighborhoodCopesWithDenseTexture) {
  SynthParams sp;
  sp.shape = BaseShape::Plane;
  sp.texture = TextureKind::Scales;
  sp.layout = TextureLayout::Dense;
  sp.size = 0.035;
  sp.amplitude = 0.01;
  sp.points = 15000;
  sp.ground_truth_points = 1;
  const SynthesizedShape s = synthesize_shape(sp);
  const double r = 1.5 * sp.size;
  const Neighborhoods R = radius_neighborhoods(s.positions, {r, 0});
  DetectTextureParams tp;
  tp.lambda = 0.05 * r;
  tp.subneighborhood = SubneighborhoodMode::Hard;
  FilterNormalsGaussianParams gp;
  gp.sigma_s = r;
  auto mean_error = [&](const Normals& M) {
    double sum = 0.0;
    for (int i = 0; i < M.rows(); ++i) sum += test::angle_deg(M.row(i), s.base_normals.row(i));
    return sum / M.rows();
  };
  const TextureDetection hard = detect_texture(s.positions, R, tp);
  tp.subneighborhood = SubneighborhoodMode::Soft;
  const TextureDetection soft = detect_texture(s.positions, R, tp);
  const double hard_error =
      mean_error(filter_normals_gaussian(s.positions, s.normals, R, hard.omega, gp).normals);
  const double soft_error =
      mean_error(filter_normals_gaussian(s.positions, s.normals, R, soft.omega, gp).normals);
  EXPECT_GT(mean_error(s.normals), 10.0) << "the scales are steep in the input";
  EXPECT_LT(soft_error, 0.75 * hard_error) << "hard " << hard_error << ", soft " << soft_error;
}

TEST(FilterNormalsGaussian, EmptySubNeighborhoodFallsBackToAllNeighbors) {
  const auto s = test::bumpy_plane(11, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.15, 0});
  const std::vector<float> all_texture(s.P.rows(), 0.0f);
  FilterNormalsGaussianParams gp;
  gp.sigma_s = 0.1;
  const GaussianFilterResult g = filter_normals_gaussian(s.P, s.N, R, all_texture, gp);
  EXPECT_EQ(g.empty_subneighborhoods, static_cast<std::size_t>(s.P.rows()));
  EXPECT_LT(max_angle_to_z(g.normals), 1e-9);
}

TEST(FilterNormalsGaussian, RejectsBadSigma) {
  const auto s = test::bumpy_plane(5, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.5, 0});
  FilterNormalsGaussianParams gp;
  gp.use_subneighborhood = false;
  EXPECT_THROW(filter_normals_gaussian(s.P, s.N, R, {}, gp), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
