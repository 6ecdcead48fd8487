#include "detexture/pipeline/filter_normals_rolling.h"

#include <gtest/gtest.h>

#include "detexture/pipeline/filter_normals_gaussian.h"
#include "test_support.h"

namespace detexture {
namespace {

// A 90-degree crease: the Gaussian blurs it over a band of width ~2r; the
// rolling iterations bring it back, so that every normal off the crease line
// itself is within a few degrees of its face's normal.
TEST(FilterNormalsRolling, RecoversCreaseBlurredByGaussian) {
  const auto s = test::folded_plane(81, 90.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.06, 0});
  FilterNormalsGaussianParams gp;
  gp.sigma_s = 0.06;
  gp.use_subneighborhood = false;
  const GaussianFilterResult g = filter_normals_gaussian(s.P, s.N, R, {}, gp);
  FilterNormalsRollingParams rp;
  rp.sigma_s = 0.06;
  rp.use_subneighborhood = false;
  const RollingFilterResult r = filter_normals_rolling(s.P, s.N, g.normals, R, {}, rp);
  double worst_gauss = 0.0, worst_rolling = 0.0;
  for (int i = 0; i < s.P.rows(); ++i) {
    if ((s.P.row(i) - Eigen::RowVector3d(0.5, s.P(i, 1), 0.0)).norm() < 0.005) continue;
    worst_gauss = std::max(worst_gauss, test::angle_deg(g.normals.row(i), s.N.row(i)));
    worst_rolling = std::max(worst_rolling, test::angle_deg(r.normals.row(i), s.N.row(i)));
  }
  EXPECT_GT(worst_gauss, 20.0);
  EXPECT_LT(worst_rolling, 3.0);
  EXPECT_GE(r.iterations, 1);
}

TEST(FilterNormalsRolling, PlainAndPatchShiftGuidanceBothKeepAPlane) {
  const auto s = test::bumpy_plane(31, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  FilterNormalsRollingParams rp;
  rp.sigma_s = 0.1;
  rp.use_subneighborhood = false;
  for (GuidanceMode mode : {GuidanceMode::PatchShift, GuidanceMode::Plain}) {
    rp.guidance.mode = mode;
    const RollingFilterResult r = filter_normals_rolling(s.P, s.N, s.N, R, {}, rp);
    for (int i = 0; i < s.P.rows(); ++i)
      ASSERT_LT(test::angle_deg(r.normals.row(i), Eigen::RowVector3d(0, 0, 1)), 1e-6);
    EXPECT_EQ(r.iterations, 1) << "nothing changes, so the first iteration stops it";
  }
}

TEST(FilterNormalsRolling, RejectsBadParameters) {
  const auto s = test::bumpy_plane(5, 0.0, 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.5, 0});
  FilterNormalsRollingParams rp;
  rp.sigma_s = 0.1;
  rp.use_subneighborhood = false;
  rp.sigma_r_deg = 0.0;
  EXPECT_THROW(filter_normals_rolling(s.P, s.N, s.N, R, {}, rp), std::invalid_argument);
  rp.sigma_r_deg = 30.0;
  rp.iterations = -1;
  EXPECT_THROW(filter_normals_rolling(s.P, s.N, s.N, R, {}, rp), std::invalid_argument);
  rp.iterations = 3;
  rp.use_subneighborhood = true;
  EXPECT_THROW(filter_normals_rolling(s.P, s.N, s.N, R, {}, rp), std::invalid_argument)
      << "Ω_i needs texture labels";
}

}  // namespace
}  // namespace detexture
