#include "detexture/pipeline/fit_normals_to_positions.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <functional>
#include <random>
#include <stdexcept>

#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"
#include "detexture/threads.h"
#include "test_support.h"

namespace detexture {
namespace {

// The fit alone (no blend), the stage's core.
FitNormalsToPositionsParams params_at(double sigma, double radius) {
  FitNormalsToPositionsParams p;
  p.sigma = sigma;
  p.radius = radius;
  p.blend_high_deg = 0.0;
  return p;
}

// The same with the default blend.
FitNormalsToPositionsParams blended_at(double sigma, double radius) {
  FitNormalsToPositionsParams p = params_at(sigma, radius);
  p.blend_high_deg = FitNormalsToPositionsParams().blend_high_deg;
  return p;
}

// Rotate every row of N by `deg` degrees about the x axis.
Normals tilted(const Normals& N, double deg) {
  const double t = deg * M_PI / 180.0;
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t);
  return N * R.transpose();
}

// A sphere's positions are exact; the guiding normals are all tilted by 10°
// (a smoothed or biased field). The fit reads the normals off the positions:
// radial, to the sampling's accuracy.
TEST(FitNormalsToPositions, SphereNormalsComeFromThePositions) {
  const auto s = test::fibonacci_sphere(20000, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  const Normals guide = tilted(s.N, 10.0);
  const FitNormalsToPositionsResult fit =
      fit_normals_to_positions(s.P, guide, R, params_at(0.03, 0.06));
  EXPECT_EQ(fit.kept, 0u);
  double worst = 0.0;
  for (int i = 0; i < s.P.rows(); ++i)
    worst = std::max(worst, test::angle_deg(fit.normals.row(i), s.N.row(i)));
  EXPECT_LT(worst, 0.5);
}

// Tilt every row of N by `deg` degrees within its tangent plane, so that
// each row turns by exactly that angle: towards N x axis, or turned from it
// by turn(i) radians about the normal when `turn` is given.
Normals tilted_in_tangent_plane(const Normals& N, double deg,
                                const std::function<double(int)>& turn = {}) {
  const double t = deg * M_PI / 180.0;
  const Eigen::RowVector3d axis = Eigen::RowVector3d(0.3, 0.5, 0.8).normalized();
  Normals out(N.rows(), 3);
  for (int i = 0; i < N.rows(); ++i) {
    Eigen::RowVector3d e = N.row(i).cross(axis);
    if (e.norm() < 1e-6) e = N.row(i).cross(Eigen::RowVector3d::UnitX());
    e.normalize();
    if (turn) {
      const double a = turn(i);
      e = std::cos(a) * e + std::sin(a) * N.row(i).cross(e);
    }
    out.row(i) = std::cos(t) * N.row(i) + std::sin(t) * e;
  }
  return out;
}

// The blend's window tests: a sphere whose positions are exact, so that the
// fit is the radial normal and turns from guides tilted in the tangent plane
// by the tilt everywhere.
struct TiltedSphere {
  test::BumpyPlane s = test::fibonacci_sphere(20000, 1.0);
  Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  Normals guide;
  FitNormalsToPositionsResult fit;   ///< with the params given
  FitNormalsToPositionsResult pure;  ///< the fit without the blend
  /// Tilt the guides by `deg` and fit with p (and without the blend).
  void tilt(double deg, const FitNormalsToPositionsParams& p) {
    guide = tilted_in_tangent_plane(s.N, deg);
    fit = fit_normals_to_positions(s.P, guide, R, p);
    pure = fit_normals_to_positions(s.P, guide, R, params_at(0.03, 0.06));
  }
};

// 0.5° (under blend_low = 1°) takes the fit, 10° (past blend_high = 2°)
// keeps the guide, 1.5° mixes them about half and half.
TEST(FitNormalsToPositions, BlendFollowsTheDisagreementWithTheGuide) {
  TiltedSphere t;
  const auto& [s, R, guide, fit, pure] = t;
  FitNormalsToPositionsParams p = blended_at(0.03, 0.06);
  ASSERT_EQ(p.blend_low_deg, 1.0);
  ASSERT_EQ(p.blend_high_deg, 2.0);
  // The mean-angle window alone (the isotropic path has its own test): near
  // the tilt axis's poles the tilt's direction turns fast.
  p.blend_coherence = 0.0;
  const auto rows = static_cast<std::size_t>(s.P.rows());
  for (const double tilt : {0.5, 1.5, 10.0}) {
    SCOPED_TRACE("tilt " + std::to_string(tilt));
    t.tilt(tilt, p);
    if (tilt == 0.5) {
      EXPECT_EQ(fit.blended, 0u);
      EXPECT_TRUE(fit.normals == pure.normals);
    } else if (tilt == 10.0) {
      EXPECT_EQ(fit.blended, rows);
      EXPECT_TRUE(fit.normals.isApprox(guide, 1e-12));
    } else {
      EXPECT_EQ(fit.blended, rows);
      for (int i = 0; i < s.P.rows(); ++i) {
        EXPECT_GT(test::angle_deg(fit.normals.row(i), pure.normals.row(i)), 0.4) << i;
        EXPECT_GT(test::angle_deg(fit.normals.row(i), guide.row(i)), 0.4) << i;
      }
    }
  }
}

// The open window (5-10°), returned beside the blend: on the sphere with
// guides tilted by 3° (past blend_high, under blend_open_low) the blend keeps
// the guide and the open output is the fit; tilted by 7.5° (halfway through
// the window) it is between the two; tilted by 12° it is the guide too.
TEST(FitNormalsToPositions, OpenWindowTakesTheFitFurther) {
  TiltedSphere t;
  const auto& [s, R, guide, fit, pure] = t;
  FitNormalsToPositionsParams p = blended_at(0.03, 0.06);
  ASSERT_EQ(p.blend_open_low_deg, 5.0);
  ASSERT_EQ(p.blend_open_high_deg, 10.0);
  p.blend_coherence = 0.0;
  const auto rows = static_cast<std::size_t>(s.P.rows());
  for (const double tilt : {3.0, 7.5, 12.0}) {
    SCOPED_TRACE("tilt " + std::to_string(tilt));
    t.tilt(tilt, p);
    EXPECT_TRUE(fit.normals.isApprox(guide, 1e-12));
    EXPECT_EQ(fit.blended, rows);
    ASSERT_EQ(fit.open.rows(), s.P.rows());
    if (tilt == 3.0) {
      EXPECT_EQ(fit.open_blended, 0u);
      EXPECT_TRUE(fit.open == pure.normals);
    } else if (tilt == 12.0) {
      EXPECT_EQ(fit.open_blended, rows);
      EXPECT_TRUE(fit.open.isApprox(guide, 1e-12));
    } else {
      EXPECT_EQ(fit.open_blended, rows);
      for (int i = 0; i < s.P.rows(); ++i) {
        EXPECT_GT(test::angle_deg(fit.open.row(i), pure.normals.row(i)), 2.0) << i;
        EXPECT_GT(test::angle_deg(fit.open.row(i), guide.row(i)), 2.0) << i;
      }
    }
  }
  EXPECT_EQ(fit_normals_to_positions(s.P, s.N, R, params_at(0.03, 0.06)).open.rows(), 0)
      << "no open output without the blend";
  p.blend_open_low_deg = 10.0;
  p.blend_open_high_deg = 5.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  p.blend_open_low_deg = 5.0;
  p.blend_open_high_deg = 200.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
}

// The isotropic path: guides tilted by 2.2° (past blend_high = 2°, under
// blend_isotropic_high - 1° = 2.5°) about a direction that changes from
// point to point, as where the positions hold facets or small features the
// guide smooths over: the departures have no one direction (κ about 0.5),
// so the fit is taken. Tilted the same way everywhere (κ about 1, as across
// waves) or with the path off (blend_coherence = 0), the guide is kept.
TEST(FitNormalsToPositions, BlendTakesTheFitWhereDeparturesHaveNoOneDirection) {
  const auto s = test::fibonacci_sphere(20000, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.08, 0});
  FitNormalsToPositionsParams p = blended_at(0.03, 0.06);
  ASSERT_EQ(p.blend_coherence, 0.9);
  ASSERT_EQ(p.blend_isotropic_high_deg, 3.5);
  // The fit is radial to 0.5°, so ā lies within 2.2 ± 0.5°: open the path
  // fully up to 4° (it ramps down from 5°).
  p.blend_isotropic_high_deg = 5.0;
  std::mt19937 random(1);  // fixed seed: the same directions on every run
  std::uniform_real_distribution<double> turn(0.0, 2.0 * M_PI);
  // A tangent direction drawn at random for each point.
  const Normals scattered = tilted_in_tangent_plane(s.N, 2.2, [&](int) { return turn(random); });
  const Normals pure = fit_normals_to_positions(s.P, scattered, R, params_at(0.03, 0.06)).normals;
  const FitNormalsToPositionsResult taken = fit_normals_to_positions(s.P, scattered, R, p);
  // Every point not blended is the fit itself, bit for bit.
  EXPECT_LT(taken.blended, static_cast<std::size_t>(s.P.rows()) / 100);
  int same = 0;
  for (int i = 0; i < s.P.rows(); ++i) same += taken.normals.row(i) == pure.row(i);
  EXPECT_EQ(static_cast<std::size_t>(same), static_cast<std::size_t>(s.P.rows()) - taken.blended);
  FitNormalsToPositionsParams off = p;
  off.blend_coherence = 0.0;
  EXPECT_TRUE(fit_normals_to_positions(s.P, scattered, R, off).normals.isApprox(scattered, 1e-12));
  // Tilted about one axis, the departures share a direction except near the
  // axis's two poles, where it turns fast: the guide stays elsewhere.
  const Normals aligned = tilted_in_tangent_plane(s.N, 2.2);
  const Normals kept = fit_normals_to_positions(s.P, aligned, R, p).normals;
  const Eigen::RowVector3d axis = Eigen::RowVector3d(0.3, 0.5, 0.8).normalized();
  int guided = 0, far_from_poles = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    if (std::abs(s.N.row(i).dot(axis)) > 0.9) continue;
    ++far_from_poles;
    guided += test::angle_deg(kept.row(i), aligned.row(i)) < 1e-5;
  }
  EXPECT_EQ(guided, far_from_poles);
  off.blend_coherence = 1.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, scattered, R, off), std::invalid_argument);
}

// The blend is local: a flat sheet guided by normals 0.5° off +z, whose
// positions are flat for x < 0.5 and keep waves (0.01 high, period 0.1) for
// x > 0.5. On the flat half (away from the waves) the fit, +z, is taken;
// on the waves the fit follows them and the guide is kept.
TEST(FitNormalsToPositions, BlendKeepsTheGuideWhereWavesRemain) {
  auto s = test::bumpy_plane(101, 0.0, 1.0);
  for (int i = 0; i < s.P.rows(); ++i)
    if (s.P(i, 0) > 0.5) s.P(i, 2) = 0.01 * std::sin(2.0 * M_PI * (s.P(i, 0) - 0.5) / 0.1);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.05, 0});
  const Normals guide = tilted(s.N, 0.5);
  const FitNormalsToPositionsResult fit =
      fit_normals_to_positions(s.P, guide, R, blended_at(0.015, 0.05));
  for (int i = 0; i < s.P.rows(); ++i) {
    if (s.P(i, 0) < 0.4) {
      EXPECT_LT(test::angle_deg(fit.normals.row(i), Eigen::RowVector3d(0, 0, 1)), 0.01) << i;
    } else if (s.P(i, 0) > 0.6) {
      EXPECT_LT(test::angle_deg(fit.normals.row(i), guide.row(i)), 1e-9) << i;
    }
  }
}

// The sign follows the guiding normal, whichever way it points.
TEST(FitNormalsToPositions, SignFollowsTheGuide) {
  const auto s = test::fibonacci_sphere(5000, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.15, 0});
  const Normals inward = -s.N;
  const FitNormalsToPositionsResult fit =
      fit_normals_to_positions(s.P, inward, R, params_at(0.06, 0.12));
  for (int i = 0; i < s.P.rows(); ++i) EXPECT_LT(fit.normals.row(i).dot(s.N.row(i)), -0.99);
}

// On test::folded_plane(side, ·): the mean angle between `a` and `b` over
// the points whose grid x (before folding) is within `near` of the crease,
// and the largest angle over those farther than `far`.
struct CreaseAngles {
  double near_mean = 0.0;
  double far_worst = 0.0;
};
CreaseAngles crease_angles(const Normals& a, const Normals& b, int side, double near, double far) {
  CreaseAngles c;
  int count = 0;
  for (int i = 0; i < a.rows(); ++i) {
    const double from_crease = std::abs(i / side / (side - 1.0) - 0.5);
    const double angle = test::angle_deg(a.row(i), b.row(i));
    if (from_crease > far) c.far_worst = std::max(c.far_worst, angle);
    if (from_crease > near) continue;
    c.near_mean += angle;
    ++count;
  }
  c.near_mean /= count;
  return c;
}

// A 90° crease with exact face normals as the guide: the range weight keeps
// each fit on its own face, up to the crease line, within 1°; without it (σr huge) the
// points next to the crease fit a plane across both faces.
TEST(FitNormalsToPositions, RangeWeightKeepsCreasesSharp) {
  const auto s = test::folded_plane(61, 90.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  FitNormalsToPositionsParams p = params_at(0.03, 0.05);
  const FitNormalsToPositionsResult sharp = fit_normals_to_positions(s.P, s.N, R, p);
  p.range_sigma = 1e3;
  p.max_turn_deg = 180.0;
  const FitNormalsToPositionsResult blurred = fit_normals_to_positions(s.P, s.N, R, p);
  double worst_sharp = 0.0, worst_blurred = 0.0;
  for (int i = 0; i < s.P.rows(); ++i) {
    worst_sharp = std::max(worst_sharp, test::angle_deg(sharp.normals.row(i), s.N.row(i)));
    worst_blurred = std::max(worst_blurred, test::angle_deg(blurred.normals.row(i), s.N.row(i)));
  }
  EXPECT_LT(worst_sharp, 1.0);  // a 90° neighbor still weighs exp(-1/(2·0.3²)) = 0.004
  EXPECT_GT(worst_blurred, 20.0);
}

// The range weights read from other normals than the guide (remove_texture
// passes the input normals): the guide is the exact fold's normals rounded
// over 0.1 on either side of a 90° crease, as a filter at that scale leaves
// them. Weighed by the guide's range, the fits near the crease lean across
// it (the guide turns by under 45° between neighbors there); by the exact
// normals', each stays on its own face (a neighbor across weighs 0.004, as
// in RangeWeightKeepsCreasesSharp). Far from the crease, where both agree,
// the fits are the same.
TEST(FitNormalsToPositions, RangeNormalsKeepTheFitOnItsFace) {
  const auto s = test::folded_plane(61, 90.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  Normals rounded = s.N;
  for (int i = 0; i < s.P.rows(); ++i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (std::size_t k = 0; k < R.count(i); ++k) sum += s.N.row(R.begin(i)[k]);
    rounded.row(i) = sum.normalized();
  }
  FitNormalsToPositionsParams p = params_at(0.04, 0.08);
  p.fine_ratio = 0.0;
  const Normals by_guide = fit_normals_to_positions(s.P, rounded, R, p).normals;
  const Normals by_exact = fit_normals_to_positions(s.P, rounded, s.N, R, p).normals;
  EXPECT_TRUE(fit_normals_to_positions(s.P, rounded, rounded, R, p).normals == by_guide)
      << "the guide as its own range normals is the three-argument call";
  const double near_guide = crease_angles(by_guide, s.N, 61, 0.1, 0.2).near_mean;
  const double near_exact = crease_angles(by_exact, s.N, 61, 0.1, 0.2).near_mean;
  const double far_gap = crease_angles(by_guide, by_exact, 61, 0.1, 0.2).far_worst;
  EXPECT_GT(near_guide, 5.0);
  EXPECT_LT(near_exact, 0.1 * near_guide);
  EXPECT_LT(far_gap, 1e-4);
}

// Range normals with zero rows (an input point without a normal): the pairs
// that touch one are weighed by the guide, as without range normals.
TEST(FitNormalsToPositions, ZeroRangeNormalsFallBackToTheGuide) {
  const auto s = test::folded_plane(41, 40.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  FitNormalsToPositionsParams p = params_at(0.04, 0.08);
  const Normals none = Normals::Zero(s.P.rows(), 3);
  EXPECT_TRUE(fit_normals_to_positions(s.P, s.N, none, R, p).normals ==
              fit_normals_to_positions(s.P, s.N, R, p).normals);
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, s.N.topRows(5), R, p), std::invalid_argument);
}

// The fine scale on a shallow crease (20°, as between the facets of a
// low-poly model; the range weight barely separates the faces there). The
// fit at σ leans across the crease up to about σ from it; the fine fit, σ/2,
// half as far, and the positions hold no noise to make it doubt. Far from
// the crease both are exact.
TEST(FitNormalsToPositions, FineScaleFollowsAShallowCrease) {
  const auto s = test::folded_plane(81, 20.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  FitNormalsToPositionsParams p = params_at(0.04, 0.08);
  ASSERT_EQ(p.fine_ratio, 0.5);
  const FitNormalsToPositionsResult fine = fit_normals_to_positions(s.P, s.N, R, p);
  p.fine_ratio = 0.0;
  const FitNormalsToPositionsResult one = fit_normals_to_positions(s.P, s.N, R, p);
  const CreaseAngles fine_angles = crease_angles(fine.normals, s.N, 81, 0.1, 0.1);
  const double near_fine = fine_angles.near_mean, far_worst = fine_angles.far_worst;
  const double near_one = crease_angles(one.normals, s.N, 81, 0.1, 0.1).near_mean;
  EXPECT_GT(near_one, 1.0);
  EXPECT_LT(near_fine, 0.7 * near_one);
  EXPECT_LT(far_worst, 1e-6);
}

// The fine scale on noise: a plane whose heights carry noise of 0.2 of the
// spacing. The fine fit departs from the fit at σ by about its own noise
// angle, so it is seldom taken, and the normals stay nearly as good as
// at σ alone; a fit at σ/2 everywhere follows the noise.
TEST(FitNormalsToPositions, FineScaleIsNotTakenForNoise) {
  auto s = test::bumpy_plane(81, 0.0, 1.0);
  std::mt19937 gen(7);
  std::normal_distribution<double> noise(0.0, 0.2 / 80.0);
  for (int i = 0; i < s.P.rows(); ++i) s.P(i, 2) = noise(gen);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  const auto mean_error = [&](const FitNormalsToPositionsParams& p) {
    const Normals fit = fit_normals_to_positions(s.P, s.N, R, p).normals;
    double sum = 0.0;
    for (int i = 0; i < s.P.rows(); ++i) sum += test::angle_deg(fit.row(i), s.N.row(i));
    return sum / static_cast<double>(s.P.rows());
  };
  FitNormalsToPositionsParams p = params_at(0.04, 0.08);
  const double fine = mean_error(p);
  p.fine_ratio = 0.0;
  const double one = mean_error(p);
  p.sigma = 0.02;
  const double half = mean_error(p);
  EXPECT_GT(half, 1.5 * one);
  EXPECT_LT(fine, 1.1 * one);
}

// A flat sheet guided by normals 60° off: the fit (+z) would turn by 60°,
// past max_turn_deg = 45, so every point keeps its guide; at 90 it is taken.
TEST(FitNormalsToPositions, LargeTurnsAreRefused) {
  const auto s = test::bumpy_plane(41, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.1, 0});
  const Normals guide = tilted(s.N, 60.0);
  FitNormalsToPositionsParams p = params_at(0.05, 0.1);
  const FitNormalsToPositionsResult refused = fit_normals_to_positions(s.P, guide, R, p);
  EXPECT_EQ(refused.kept, static_cast<std::size_t>(s.P.rows()));
  EXPECT_TRUE(refused.normals.isApprox(guide));
  p.max_turn_deg = 90.0;
  const FitNormalsToPositionsResult taken = fit_normals_to_positions(s.P, guide, R, p);
  EXPECT_EQ(taken.kept, 0u);
  for (int i = 0; i < s.P.rows(); ++i) EXPECT_NEAR(taken.normals(i, 2), 1.0, 1e-12);
}

// Too few neighbors, collinear neighbors, neighbors beyond ρ, zero normals:
// the guide is kept and counted (zero normals stay zero, uncounted).
TEST(FitNormalsToPositions, DegenerateNeighborhoodsKeepTheGuide) {
  Positions P(7, 3);
  P << 0, 0, 0,                                      // alone
      10, 0, 0, 10.1, 0, 0, 10.2, 0, 0, 10.3, 0, 0,  // collinear
      20, 0, 0, 20, 0.05, 0;                         // two points only
  Normals N(7, 3);
  N.setZero();
  N.col(2).setOnes();
  N.row(6).setZero();
  const Neighborhoods R = radius_neighborhoods(P, {0.5, 0});
  const FitNormalsToPositionsResult fit = fit_normals_to_positions(P, N, R, params_at(0.2, 0.5));
  EXPECT_EQ(fit.kept, 6u);
  EXPECT_TRUE(fit.normals.isApprox(N));
  EXPECT_EQ(fit.normals.row(6).squaredNorm(), 0.0);
}

TEST(FitNormalsToPositions, BadInputIsRefused) {
  const auto s = test::bumpy_plane(11, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.2, 0});
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, params_at(0.0, 0.1)), std::invalid_argument);
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, params_at(0.1, -1.0)), std::invalid_argument);
  FitNormalsToPositionsParams p = params_at(0.1, 0.1);
  p.range_sigma = 0.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  p = params_at(0.1, 0.1);
  p.max_turn_deg = 200.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  p = blended_at(0.1, 0.1);
  p.blend_high_deg = -1.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  p = blended_at(0.1, 0.1);
  p.blend_low_deg = p.blend_high_deg;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  p.blend_low_deg = -0.5;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  for (const double ratio : {-0.1, 1.0}) {
    p = params_at(0.1, 0.1);
    p.fine_ratio = ratio;
    EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  }
  p = params_at(0.1, 0.1);
  p.fine_gamma = -1.0;
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N, R, p), std::invalid_argument);
  EXPECT_THROW(fit_normals_to_positions(s.P, s.N.topRows(5), R, params_at(0.1, 0.1)),
               std::invalid_argument);
  RemoveTextureParams rp;
  rp.fit_sigma = Length{0.0, Length::Unit::Radius};
  EXPECT_THROW(validate(rp), std::invalid_argument);
}

// A unit sphere of 20000 points (in a test::BumpyPlane: its P and N) with 12
// bumps: the points near 12 centres pushed outwards by a smooth dome 0.03
// high.
test::BumpyPlane sphere_with_bumps() {
  auto s = test::fibonacci_sphere(20000, 1.0);
  const auto centres = test::fibonacci_sphere(12, 1.0);
  for (int i = 0; i < s.P.rows(); ++i)
    for (int c = 0; c < centres.P.rows(); ++c) {
      const double d = (s.N.row(i) - centres.N.row(c)).norm();
      if (d < 0.15) s.P.row(i) += 0.03 * std::exp(-d * d / (2 * 0.05 * 0.05)) * s.N.row(i);
    }
  return s;
}

// Waves left (the flags remove_texture's second pass reads): the same sheet
// with longer waves (period 0.3, ρ = 0.05), so that a neighborhood sees a
// third of a period. Across a crest or a trough the fit's departure from the
// guide changes sign steadily along x: flagged. The flat half is not (ā
// 0.5°, under waves_min_deg); nor is anything with waves_min_deg 0, nor a
// guide tilted the same way everywhere on a flat sheet (the departures do
// not vary with the position).
TEST(FitNormalsToPositions, WavesLeftAreFlaggedAtTheirCrestsAndTroughs) {
  auto s = test::bumpy_plane(121, 0.0, 1.0);
  const double period = 0.3;
  for (int i = 0; i < s.P.rows(); ++i)
    if (s.P(i, 0) > 0.4) s.P(i, 2) = 0.01 * std::sin(2.0 * M_PI * (s.P(i, 0) - 0.4) / period);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.05, 0});
  const Normals guide = tilted(s.N, 0.5);
  FitNormalsToPositionsParams p = blended_at(0.015, 0.05);
  ASSERT_EQ(p.waves_min_deg, 2.0);
  const FitNormalsToPositionsResult fit = fit_normals_to_positions(s.P, guide, R, p);
  ASSERT_EQ(fit.waves.size(), static_cast<std::size_t>(s.P.rows()));
  int flat = 0, crests = 0, crest_points = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double x = s.P(i, 0), y = s.P(i, 1);
    if (y < 0.1 || y > 0.9) continue;  // away from the sheet's open sides
    if (x < 0.3) flat += fit.waves[static_cast<std::size_t>(i)];
    // Within 0.03 of a crest (x = 0.475, 0.775) or a trough (0.625, 0.925).
    const double phase = std::fmod(x - 0.4 + period, period / 2.0);
    if (x > 0.45 && x < 0.94 && std::abs(phase - period / 4.0) < 0.03) {
      ++crest_points;
      crests += fit.waves[static_cast<std::size_t>(i)];
    }
  }
  EXPECT_EQ(flat, 0);
  ASSERT_GT(crest_points, 0);
  EXPECT_GT(crests, crest_points * 3 / 4);
  p.waves_min_deg = 0.0;
  EXPECT_TRUE(fit_normals_to_positions(s.P, guide, R, p).waves.empty());
  p.waves_min_deg = 2.0;
  const auto flat_sheet = test::bumpy_plane(81, 0.0, 1.0);
  const Neighborhoods Rf = radius_neighborhoods(flat_sheet.P, {0.05, 0});
  const FitNormalsToPositionsResult tilted3 =
      fit_normals_to_positions(flat_sheet.P, tilted(flat_sheet.N, 3.0), Rf, p);
  int flagged = 0;
  for (std::uint8_t f : tilted3.waves) flagged += f;
  EXPECT_EQ(flagged, 0);
  p.waves_linearity = 1.5;
  EXPECT_THROW(fit_normals_to_positions(s.P, guide, R, p), std::invalid_argument);
}

// The wavy torus's parameters with the fit's normals alone: the input
// normals kept afterwards follow the final positions (keep_input_normals.h),
// which the second pass moves.
RemoveTextureParams wavy_torus_fit_only_params() {
  RemoveTextureParams p = test::wavy_torus_params();
  p.keep_input.high = 0.0;
  p.keep_input.exact_angle_deg = 0.0;
  p.keep_input.still_angle_deg = 0.0;
  p.keep_input.reached_angle_deg = 0.0;
  return p;
}

// The spread (standard deviation) of Q's heights over the shape's base
// surface, along the base normals: the waves left in the positions.
double spread_over_base(const SynthesizedShape& shape, const Positions& Q) {
  Eigen::VectorXd h(Q.rows());
  for (int i = 0; i < Q.rows(); ++i)
    h(i) = (Q.row(i) - shape.base_positions.row(i)).dot(shape.base_normals.row(i));
  return std::sqrt((h.array() - h.mean()).square().mean());
}

// Through remove_texture, the second pass: a torus with dense waves (synth's,
// 0.04 wide and 0.016 high, 30k points; r = 1.5 × 0.04) flags more than
// wave_share_high of its surface points, and keeps less of its waves than
// with the pass off (wave_share_low 1): the spread of the output's heights
// over the base surface drops. The output normals are the first pass's. A
// sphere with a few bumps flags under wave_share_low and is left as the
// first pass made it.
TEST(FitNormalsToPositions, RemoveTextureRunsTheUpdateAgainOverWavesLeft) {
  const SynthesizedShape torus = test::wavy_torus();
  RemoveTextureParams p = wavy_torus_fit_only_params();
  const RemoveTextureResult on = remove_texture(torus.positions, Normals(), p);
  p.wave_share_low = 1.0;
  const RemoveTextureResult off = remove_texture(torus.positions, Normals(), p);
  EXPECT_EQ(off.report.waves_released, 0u);
  EXPECT_EQ(on.report.waves_flagged, off.report.waves_flagged);
  const std::size_t surface = on.positions.rows() - on.report.texture_points;
  EXPECT_GT(on.report.waves_flagged, static_cast<std::size_t>(p.wave_share_high * surface));
  EXPECT_EQ(on.report.waves_released, on.report.waves_flagged);
  EXPECT_LT(spread_over_base(torus, on.positions), 0.92 * spread_over_base(torus, off.positions));
  EXPECT_TRUE(on.normals == off.normals) << "the output normals are the first pass's";
  // A sphere with bumps: few flags, no second pass, the same output.
  const auto s = sphere_with_bumps();
  p.wave_share_low = RemoveTextureParams().wave_share_low;
  const RemoveTextureResult bumps = remove_texture(s.P, Normals(), p);
  EXPECT_EQ(bumps.report.waves_released, 0u);
  p.wave_share_low = 1.0;
  EXPECT_TRUE(remove_texture(s.P, Normals(), p).positions == bumps.positions);
  p.wave_share_low = 0.3;
  p.wave_share_high = 0.2;
  EXPECT_THROW(remove_texture(s.P, Normals(), p), std::invalid_argument);
}

// The wavy torus run through remove_texture at wavy_torus_fit_only_params()
// and again with `change` applied (p holds the change afterwards); the
// second pass must run in the first.
struct TorusRuns {
  SynthesizedShape torus;
  RemoveTextureParams p;
  RemoveTextureResult defaults, changed;
};

TorusRuns wavy_torus_with_and_without(const std::function<void(RemoveTextureParams&)>& change) {
  TorusRuns r{test::wavy_torus(), wavy_torus_fit_only_params(), {}, {}};
  r.defaults = remove_texture(r.torus.positions, Normals(), r.p);
  change(r.p);
  r.changed = remove_texture(r.torus.positions, Normals(), r.p);
  EXPECT_GT(r.defaults.report.waves_released, 0u);
  return r;
}

// Through remove_texture, the second pass's other surface points
// (wave_rest_anchor): on the wavy torus, holding them less lowers the spread
// of the output's heights over the base surface below what the flagged
// points alone give (wave_rest_anchor 1, before session 38), with the same
// flags and the same output normals. The factor must lie in (0, 1].
TEST(FitNormalsToPositions, RemoveTextureHoldsTheWavesFlanksLessInTheSecondPass) {
  ASSERT_EQ(RemoveTextureParams().wave_rest_anchor, 0.3);
  auto [torus, p, rest, flagged_only] =
      wavy_torus_with_and_without([](RemoveTextureParams& q) { q.wave_rest_anchor = 1.0; });
  EXPECT_EQ(rest.report.waves_released, flagged_only.report.waves_released);
  EXPECT_LT(spread_over_base(torus, rest.positions),
            0.97 * spread_over_base(torus, flagged_only.positions));
  EXPECT_TRUE(rest.normals == flagged_only.normals) << "the output normals are the first pass's";
  for (double bad : {0.0, -0.5, 1.5}) {
    p.wave_rest_anchor = bad;
    EXPECT_THROW(remove_texture(torus.positions, Normals(), p), std::invalid_argument) << bad;
  }
}

// Through remove_texture, the second pass's ceiling (wave_ceiling): on the
// wavy torus, with the ceiling (1 λ, the default) the second pass cuts some
// outward moves of crests and inward moves of troughs; with it off (0,
// before session 39) nothing is limited. The points that differ differ
// along their input normals and end nearer the base surface (in the sum of
// their distances), and the spread of the heights stays within 1% (the
// texture removed stays removed). Without the second pass (wave_share_low
// 1), the ceiling changes nothing. Negative or infinite values are refused.
TEST(FitNormalsToPositions, RemoveTextureCeilsTheSecondPassesMoves) {
  ASSERT_EQ(RemoveTextureParams().wave_ceiling, 1.0);
  auto [torus, p, ceiled, free] =
      wavy_torus_with_and_without([](RemoveTextureParams& q) { q.wave_ceiling = 0.0; });
  EXPECT_GT(ceiled.report.tip_moves_limited, 50u);
  EXPECT_EQ(free.report.tip_moves_limited, 0u);
  const auto off_base = [&](const Positions& Q, int i) {
    return std::abs((Q.row(i) - torus.base_positions.row(i)).dot(torus.base_normals.row(i)));
  };
  std::size_t differ = 0;
  double off_ceiled = 0.0, off_free = 0.0;
  for (int i = 0; i < torus.positions.rows(); ++i) {
    const Eigen::RowVector3d d = ceiled.positions.row(i) - free.positions.row(i);
    if (d.norm() == 0.0) continue;
    ++differ;
    EXPECT_GT(std::abs(d.dot(ceiled.input_normals.row(i))), 0.999 * d.norm()) << i;
    off_ceiled += off_base(ceiled.positions, i);
    off_free += off_base(free.positions, i);
  }
  EXPECT_GT(differ, 50u);
  EXPECT_LT(off_ceiled, 0.97 * off_free);
  EXPECT_LT(spread_over_base(torus, ceiled.positions),
            1.01 * spread_over_base(torus, free.positions));
  p.wave_share_low = 1.0;
  const RemoveTextureResult once = remove_texture(torus.positions, Normals(), p);
  p.wave_ceiling = 1.0;
  EXPECT_TRUE(remove_texture(torus.positions, Normals(), p).positions == once.positions);
  for (double bad : {-0.5, double(INFINITY)}) {
    p.wave_ceiling = bad;
    EXPECT_THROW(remove_texture(torus.positions, Normals(), p), std::invalid_argument) << bad;
  }
}

// Through remove_texture, the blend's gate: synth's cube with bumps (20k
// points, default parameters) flags almost no waves (under blend_share_low),
// so its output normals are the open window's, the same as the blend with
// its window set to 5-10° on every cloud (blend_share_high 0), and blend
// fewer points than the blend's own window does (its edges, rounded by the
// filtered normals). The torus with waves flags more than blend_share_high
// and keeps the blend's own window. Bad shares are refused.
TEST(FitNormalsToPositions, RemoveTextureOpensTheBlendWhereNoWavesAreLeft) {
  SynthParams cp;
  cp.points = 20000;
  cp.ground_truth_points = 1;
  const SynthesizedShape cube = synthesize_shape(cp);
  RemoveTextureParams p;
  ASSERT_EQ(p.blend_share_low, 0.05);
  ASSERT_EQ(p.blend_share_high, 0.1);
  p.threads = 2;
  const RemoveTextureResult gated = remove_texture(cube.positions, cube.normals, p);
  EXPECT_LT(gated.report.waves_flagged,
            static_cast<std::size_t>(p.blend_share_low *
                                     (gated.positions.rows() - gated.report.texture_points)));
  p.blend_share_high = 0.0;
  const RemoveTextureResult always = remove_texture(cube.positions, cube.normals, p);
  EXPECT_TRUE(gated.positions == always.positions);
  EXPECT_FALSE(gated.normals == always.normals);
  EXPECT_LT(gated.report.normals_blended, always.report.normals_blended);
  p.output_normals.blend_low_deg = p.output_normals.blend_open_low_deg;
  p.output_normals.blend_high_deg = p.output_normals.blend_open_high_deg;
  p.output_normals.blend_coherence = 0.0;
  const RemoveTextureResult wide = remove_texture(cube.positions, cube.normals, p);
  EXPECT_TRUE(gated.normals == wide.normals);
  EXPECT_EQ(gated.report.normals_blended, wide.report.normals_blended);

  const SynthesizedShape torus = test::wavy_torus();
  RemoveTextureParams q = test::wavy_torus_params();
  const RemoveTextureResult waves = remove_texture(torus.positions, Normals(), q);
  EXPECT_GT(waves.report.waves_flagged,
            static_cast<std::size_t>(q.blend_share_high *
                                     (waves.positions.rows() - waves.report.texture_points)));
  q.blend_share_high = 0.0;
  EXPECT_TRUE(remove_texture(torus.positions, Normals(), q).normals == waves.normals);

  p = RemoveTextureParams();
  p.blend_share_low = 0.2;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.blend_share_low = -0.1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.blend_share_low = 0.5;
  p.blend_share_high = 0.0;
  EXPECT_NO_THROW(validate(p)) << "blend_share_high 0 blends on every cloud";
  p.blend_share_high = 1.5;
  EXPECT_THROW(validate(p), std::invalid_argument);
}

// Through remove_texture: the fit's range weights read the input normals when
// the input has them (a cube with bumps and synth's exact normals), which
// changes the output normals only; an input without normals, whose normals
// are estimated, is weighed by the filtered ones either way.
TEST(FitNormalsToPositions, RemoveTextureRangeReadsTheInputNormals) {
  SynthParams cp;
  cp.points = 6000;
  cp.ground_truth_points = 1;
  const SynthesizedShape cube = synthesize_shape(cp);
  RemoveTextureParams p;
  ASSERT_TRUE(p.fit_range_input_normals);
  p.threads = 2;
  const RemoveTextureResult input = remove_texture(cube.positions, cube.normals, p);
  const RemoveTextureResult estimated = remove_texture(cube.positions, Normals(), p);
  p.fit_range_input_normals = false;
  const RemoveTextureResult filtered = remove_texture(cube.positions, cube.normals, p);
  EXPECT_TRUE(input.positions == filtered.positions);
  EXPECT_FALSE(input.normals == filtered.normals);
  EXPECT_TRUE(remove_texture(cube.positions, Normals(), p).normals == estimated.normals);
}

// Through remove_texture: the output normals (filtered, the paper; fitted;
// blended, the default) change the normals only, and the same on any thread
// count; on a sphere with bumps the fitted and the blended normals are closer
// to the true (radial) ones than the filtered normals are.
TEST(FitNormalsToPositions, RemoveTextureOptionChangesOnlyTheNormals) {
  const auto s = sphere_with_bumps();
  RemoveTextureParams p;
  ASSERT_TRUE(p.fit_normals) << "blended output normals are the default";
  p.keep_input.high = 0.0;  // the fit and its blend alone (test_keep_input_normals.cpp)
  p.keep_input.exact_angle_deg = 0.0;
  p.keep_input.still_angle_deg = 0.0;
  p.keep_input.reached_angle_deg = 0.0;
  p.radius = Length{0.15, Length::Unit::Absolute};
  p.threads = 1;
  const RemoveTextureResult blended = remove_texture(s.P, Normals(), p);
  p.threads = 2;
  const RemoveTextureResult blended2 = remove_texture(s.P, Normals(), p);
  p.output_normals.blend_high_deg = 0.0;
  const RemoveTextureResult fitted = remove_texture(s.P, Normals(), p);
  p.fit_normals = false;
  const RemoveTextureResult filtered = remove_texture(s.P, Normals(), p);
  EXPECT_TRUE(fitted.positions == filtered.positions);
  EXPECT_TRUE(blended.positions == filtered.positions);
  EXPECT_TRUE(blended.normals == blended2.normals);
  EXPECT_FALSE(fitted.normals == filtered.normals);
  // The output positions are smooth here: the fit agrees with the filtered
  // normals within blend_low around every point and is taken everywhere.
  EXPECT_TRUE(blended.normals == fitted.normals);
  EXPECT_EQ(blended.report.normals_blended, 0u);
  EXPECT_EQ(filtered.report.normals_not_fitted, 0u);
  EXPECT_EQ(filtered.report.normals_blended, 0u);
  EXPECT_EQ(fitted.report.normals_blended, 0u);
  // A window closed to almost nothing keeps the filtered normals instead,
  // on every cloud (the gate would open it here: no waves).
  p.fit_normals = true;
  p.blend_share_high = 0.0;
  p.output_normals.blend_coherence = 0.0;
  p.output_normals.blend_low_deg = 0.0;
  p.output_normals.blend_high_deg = 1e-3;
  const RemoveTextureResult narrow = remove_texture(s.P, Normals(), p);
  p.threads = 1;
  const RemoveTextureResult narrow1 = remove_texture(s.P, Normals(), p);
  EXPECT_GT(narrow.report.normals_blended, narrow.positions.rows() / 2);
  EXPECT_LT((narrow.normals - filtered.normals).cwiseAbs().maxCoeff(), 0.01);
  EXPECT_TRUE(narrow.normals == narrow1.normals) << "the mixing, on 2 threads and on 1";
  auto mean_error = [&](const RemoveTextureResult& r) {
    double sum = 0.0;
    for (int i = 0; i < r.positions.rows(); ++i)
      sum += test::angle_deg(r.normals.row(i), r.positions.row(i).normalized());
    return sum / r.positions.rows();
  };
  EXPECT_LT(mean_error(fitted), 0.8 * mean_error(filtered));
  EXPECT_LT(mean_error(blended), 0.8 * mean_error(filtered));
}

}  // namespace
}  // namespace detexture
