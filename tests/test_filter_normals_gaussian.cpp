#include "detexture/pipeline/filter_normals_gaussian.h"

#include <gtest/gtest.h>

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
  const GaussianFilterResult sub = filter_normals_gaussian(s.P, s.N, R, det.is_texture, gp);
  gp.use_subneighborhood = false;
  const GaussianFilterResult plain = filter_normals_gaussian(s.P, s.N, R, {}, gp);
  EXPECT_EQ(sub.empty_subneighborhoods, 0u);
  EXPECT_LT(max_angle_to_z(sub.normals), 3.0);
  EXPECT_GT(max_angle_to_z(plain.normals), 2.0 * max_angle_to_z(sub.normals));
  EXPECT_GT(max_angle_to_z(s.N), 30.0) << "the bump is steep in the input";
}

TEST(FilterNormalsGaussian, EmptySubNeighborhoodFallsBackToAllNeighbors) {
  const auto s = test::bumpy_plane(11, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.15, 0});
  std::vector<std::uint8_t> all_texture(s.P.rows(), 1);
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
