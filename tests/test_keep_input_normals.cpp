#include "detexture/pipeline/keep_input_normals.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "detexture/eval/compare_to_ground_truth.h"
#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"
#include "test_support.h"

namespace detexture {
namespace {

// The tests of the earlier paths read them alone: the reach after them
// (reached_angle_deg) would take more, and has its own test below.
KeepInputNormalsParams params_at(double radius, double lambda) {
  KeepInputNormalsParams p;
  p.radius = radius;
  p.lambda = lambda;
  p.reached_angle_deg = 0.0;
  return p;
}

// 10 x of the points first..last (one row of a grid) whose output took the
// input normal `in`; every other one must have kept `output`.
std::vector<int> taken_tenths(const KeepInputNormalsResult& r, const Positions& P,
                              const Normals& in, const Normals& output, int first, int last) {
  std::vector<int> tenths;
  for (int i = first; i <= last; ++i) {
    if (test::angle_deg(r.normals.row(i), in.row(i)) < 1e-9)
      tenths.push_back(static_cast<int>(std::lround(P(i, 0) * 10.0)));
    else
      EXPECT_TRUE(r.normals.row(i) == output.row(i)) << i;
  }
  return tenths;
}

// A flat grid (spacing 0.1, x and y in [-1, 1], z = 0) with exact input
// normals +z and output normals tilted about y by 50° x², as a rounded
// surface's would be; neighborhoods of radius 0.3.
struct RoundedGrid {
  static constexpr int side = 21;
  Positions P;
  Neighborhoods R;
  Normals given, output;
  RoundedGrid() : P(side * side, 3), given(side * side, 3), output(side * side, 3) {
    for (int i = 0; i < P.rows(); ++i) {
      P.row(i) = Eigen::RowVector3d(-1.0 + 0.1 * (i % side), -1.0 + 0.1 * (i / side), 0.0);
      const double t = 50.0 * P(i, 0) * P(i, 0) * M_PI / 180.0;
      output.row(i) = Eigen::RowVector3d(std::sin(t), 0.0, std::cos(t));
    }
    given.rowwise() = Eigen::RowVector3d(0.0, 0.0, 1.0);
    R = radius_neighborhoods(P, {0.3, 0});
  }
};

// The grid above folded by `fold` (20° unless given) at x = 0.05 into two
// facets, A (x <= 0, z = 0, normal +z) and B (x >= 0.1), with exact input
// normals; output normals rounded across the fold, tilted about y by
// fold · clamp((x + 0.15) / 0.4, 0, 1).
struct FoldedGrid {
  static constexpr int side = 21;
  static constexpr double kFold = 20.0 * M_PI / 180.0;
  double fold;
  Positions P;
  Neighborhoods R;
  Normals given, output;
  explicit FoldedGrid(double fold_radians = kFold)
      : fold(fold_radians), P(side * side, 3), given(side * side, 3), output(side * side, 3) {
    for (int i = 0; i < P.rows(); ++i) {
      const double x = -1.0 + 0.1 * (i % side);
      P.row(i) = Eigen::RowVector3d(x, -1.0 + 0.1 * (i / side),
                                    x > 0.05 ? (x - 0.05) * std::tan(fold) : 0.0);
      given.row(i) = x > 0.05 ? Eigen::RowVector3d(-std::sin(fold), 0.0, std::cos(fold))
                              : Eigen::RowVector3d(0.0, 0.0, 1.0);
      const double t = fold * std::clamp((x + 0.15) / 0.4, 0.0, 1.0);
      output.row(i) = Eigen::RowVector3d(-std::sin(t), 0.0, std::cos(t));
    }
    R = radius_neighborhoods(P, {0.3, 0});
  }
};

// A plane whose points do not move, except one that moves by 1 (a bump
// taken down); the output normals so far are tilted by 10°. Points farther
// than ρ from the moved one take their input normal, exactly; the moved
// point and those within ρ of it keep the output normal, and so do texture
// points and points without an input normal.
TEST(KeepInputNormals, NormalsAreKeptWhereNothingNearMoved) {
  const auto s = test::bumpy_plane(21, 0.0, 1.0);  // a flat grid, spacing 0.05
  const Neighborhoods R = radius_neighborhoods(s.P, {0.12, 0});
  Positions updated = s.P;
  const int moved = 10 * 21 + 10;  // the centre
  updated(moved, 2) += 1.0;
  Normals output = s.N;
  const double t = 10.0 * M_PI / 180.0;
  output.col(1).setConstant(std::sin(t));
  output.col(2).setConstant(std::cos(t));
  std::vector<std::uint8_t> texture(s.P.rows(), 0);
  texture[0] = 1;
  Normals given = s.N;
  given.row(1).setZero();
  const KeepInputNormalsResult r =
      keep_input_normals(s.P, updated, given, output, texture, R, params_at(0.11, 0.01));
  std::size_t kept = 0;
  for (int i = 0; i < s.P.rows(); ++i) {
    const bool near = (s.P.row(i) - s.P.row(moved)).norm() <= 0.11;
    if (near || i == 0 || i == 1) {
      EXPECT_TRUE(r.normals.row(i) == output.row(i)) << i;
    } else {
      EXPECT_LT(test::angle_deg(r.normals.row(i), s.N.row(i)), 1e-5) << i;
      ++kept;
    }
  }
  EXPECT_EQ(r.kept, kept);
  EXPECT_GT(kept, 300u);
  // Input normals signed the other way are taken signed like the output.
  const Normals flipped = -given;
  EXPECT_TRUE(keep_input_normals(s.P, updated, flipped, output, texture, R, params_at(0.11, 0.01))
                  .normals.isApprox(r.normals, 1e-12));
}

// The ramp: every point moves by the same distance d. Under low λ the input
// normal is taken, from high λ the output normal stays, halfway between the
// two the output is their normalized mean. high = 0 changes nothing.
TEST(KeepInputNormals, TheRampFollowsTheMove) {
  const auto s = test::bumpy_plane(11, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.2, 0});
  Normals output(s.P.rows(), 3);
  output.rowwise() = Eigen::RowVector3d(1.0, 0.0, 0.0);
  const KeepInputNormalsParams p = params_at(0.15, 1.0);
  ASSERT_EQ(p.low, 0.05);
  ASSERT_EQ(p.high, 0.2);
  const auto run = [&](double d, const KeepInputNormalsParams& q) {
    Positions updated = s.P;
    updated.col(0).array() += d;
    return keep_input_normals(s.P, updated, s.N, output, {}, R, q);
  };
  const Eigen::RowVector3d mean = Eigen::RowVector3d(1.0, 0.0, 1.0).normalized();
  for (int i = 0; i < s.P.rows(); ++i) {
    EXPECT_LT(test::angle_deg(run(0.04, p).normals.row(i), s.N.row(i)), 1e-5);
    EXPECT_TRUE(run(0.2, p).normals.row(i) == output.row(i));
    EXPECT_LT(test::angle_deg(run(0.125, p).normals.row(i), mean), 1e-5);
  }
  EXPECT_EQ(run(0.125, p).kept, static_cast<std::size_t>(s.P.rows()));
  EXPECT_EQ(run(0.2, p).kept, 0u);
  KeepInputNormalsParams off = p;
  off.high = 0.0;
  EXPECT_TRUE(run(0.0, off).normals == output);
}

// Exact input normals: every point of a flat grid (spacing 0.1) moves by 1,
// so the move keeps nothing, and the output normals are tilted by t. The
// grid lies alternately a above and below z = 0 (a checkerboard), so each
// interior point's 8 nearest neighbors lie 2a (the 4 at 0.1) and 0 (the 4
// diagonal ones) off its tangent plane z = ±a: a mean of a. With λ = 0.01,
// e = 0.05: a = 0.0004 <= 0.0005 is exact, a = 0.0006 is not. The input
// normal is taken where exact and t <= θ = 4°, fully (not in part).
TEST(KeepInputNormals, ExactInputNormalsAreTakenWithinTheAngle) {
  constexpr int side = 11;
  const auto run = [&](double a, double tilt_deg, const KeepInputNormalsParams& q) {
    const auto s = test::bumpy_plane(side, 0.0, 1.0);
    Positions P = s.P;
    for (int i = 0; i < P.rows(); ++i) P(i, 2) = ((i / side + i % side) % 2 ? a : -a);
    const Neighborhoods R = radius_neighborhoods(P, {0.25, 0});
    Positions updated = P;
    updated.col(0).array() += 1.0;
    const double t = tilt_deg * M_PI / 180.0;
    Normals output(P.rows(), 3);
    output.rowwise() = Eigen::RowVector3d(0.0, std::sin(t), std::cos(t));
    const KeepInputNormalsResult r = keep_input_normals(P, updated, s.N, output, {}, R, q);
    std::size_t interior = 0, taken = 0;
    for (int i = 0; i < P.rows(); ++i) {
      if (i / side < 2 || i / side >= side - 2 || i % side < 2 || i % side >= side - 2) continue;
      ++interior;
      if (test::angle_deg(r.normals.row(i), s.N.row(i)) < 1e-9)
        ++taken;
      else
        EXPECT_TRUE(r.normals.row(i) == output.row(i)) << i;
    }
    EXPECT_EQ(interior, 49u);
    EXPECT_GE(r.exact, taken);
    EXPECT_EQ(r.kept, r.exact);
    return taken;
  };
  KeepInputNormalsParams p = params_at(0.15, 0.01);
  ASSERT_EQ(p.exact_angle_deg, 4.0);
  ASSERT_EQ(p.exact_residual, 0.05);
  ASSERT_EQ(p.exact_neighbors, 8);
  EXPECT_EQ(run(0.0004, 3.0, p), 49u);
  EXPECT_EQ(run(0.0006, 3.0, p), 0u);
  EXPECT_EQ(run(0.0, 5.0, p), 0u);
  EXPECT_EQ(run(0.0, 3.9, p), 49u);
  KeepInputNormalsParams off = p;
  off.exact_angle_deg = 0.0;
  EXPECT_EQ(run(0.0, 1.0, off), 0u);
  KeepInputNormalsParams loose = p;
  loose.exact_residual = 0.07;
  EXPECT_EQ(run(0.0006, 3.0, loose), 49u);
}

// Exact input normals where the surface stayed: a flat grid (spacing 0.1,
// x and y in [-1, 1]) with exact normals +z, moved by 0.5 λ along x, and
// output normals tilted about y by 50° x², as a rounded surface's would
// be. Within ρ = 0.25 (±0.2 in x) the output normals around x turn by up
// to 50° ((|x| + 0.2)² - x²) = 20°|x| + 2°, so the tilt 50° x² lies within
// that turn for |x| <= 0.48 (the cone, before session 25). The reach asks
// more directly: some output normal within ρ lies within α = 0.5 of the
// tilt of +z, 50° x'² <= 25° x², |x'| <= |x| / √2, which x' = x ∓ 0.2 meets
// for 0.3 <= |x| (0.1 at 0.3, 0.4 at 0.6). So at x = ±0.3 (4.5°) to ±0.6
// (18°) the input normal is taken by this test (at |x| <= 0.2, 2° at most,
// by the 4° one); at ±0.7 (24.5°) it is not, being past θ_s = 20°; with the
// cone, ±0.3 and ±0.4 only (±0.5: 12.5° against a turn of 12°). Nowhere once
// the move exceeds μ λ, nor with θ_s = 0, nor when the neighbors' input
// normals disagree by more than φ, nor above θ_s.
TEST(KeepInputNormals, ExactInputNormalsAreTakenWhereTheSurfaceStayed) {
  constexpr int side = RoundedGrid::side;
  const double lambda = 0.01;
  const RoundedGrid grid;
  const Positions& P = grid.P;
  const Neighborhoods& R = grid.R;
  const Normals& given = grid.given;
  const Normals& output = grid.output;
  const auto run = [&](double move, const Normals& in, const KeepInputNormalsParams& q) {
    Positions updated = P;
    updated.col(0).array() += move;
    return keep_input_normals(P, updated, in, output, {}, R, q);
  };
  // The columns x = -1 + 0.1 c whose input normal is taken, in row 10.
  const auto taken_x = [&](const KeepInputNormalsResult& r) {
    return taken_tenths(r, P, given, output, 10 * side, 10 * side + side - 1);
  };
  KeepInputNormalsParams p = params_at(0.25, lambda);
  ASSERT_EQ(p.still_angle_deg, 20.0);
  ASSERT_EQ(p.still_move, 3.0);
  ASSERT_EQ(p.still_move_engraved, 1.0);
  ASSERT_FALSE(p.engraved);
  ASSERT_EQ(p.still_uniform_deg, 1.0);
  ASSERT_EQ(p.still_reach, 0.5);
  const KeepInputNormalsResult r = run(0.5 * lambda, given, p);
  EXPECT_EQ(taken_x(r), (std::vector<int>{-6, -5, -4, -3, -2, -1, 0, 1, 2, 3, 4, 5, 6}));
  // Columns ±0.3 to ±0.6 of all 21 rows are taken by this test.
  EXPECT_EQ(r.still, 8u * side);
  EXPECT_EQ(r.kept, r.exact);
  KeepInputNormalsParams cone = p;
  cone.still_reach = 0.0;
  const KeepInputNormalsResult by_cone = run(0.5 * lambda, given, cone);
  EXPECT_EQ(taken_x(by_cone), (std::vector<int>{-4, -3, -2, -1, 0, 1, 2, 3, 4}));
  EXPECT_EQ(by_cone.still, 4u * side);
  // Moved farther than μ λ: only the 4° test.
  EXPECT_EQ(taken_x(run(3.5 * lambda, given, p)), (std::vector<int>{-2, -1, 0, 1, 2}));
  EXPECT_EQ(run(1.5 * lambda, given, p).still, 8u * side);
  KeepInputNormalsParams loose = p;
  loose.still_move = 4.0;
  EXPECT_EQ(run(3.5 * lambda, given, loose).still, 8u * side);
  // Where the relief reads as sparse engraving, μ is still_move_engraved.
  KeepInputNormalsParams engraved = p;
  engraved.engraved = true;
  EXPECT_EQ(taken_x(run(1.5 * lambda, given, engraved)), (std::vector<int>{-2, -1, 0, 1, 2}));
  EXPECT_EQ(run(0.5 * lambda, given, engraved).still, 8u * side);
  engraved.still_move_engraved = 2.0;
  EXPECT_EQ(run(1.5 * lambda, given, engraved).still, 8u * side);
  KeepInputNormalsParams off = p;
  off.still_angle_deg = 0.0;
  EXPECT_EQ(taken_x(run(0.5 * lambda, given, off)), (std::vector<int>{-2, -1, 0, 1, 2}));
  KeepInputNormalsParams narrow = p;
  narrow.still_angle_deg = 6.0;
  EXPECT_EQ(taken_x(run(0.5 * lambda, given, narrow)), (std::vector<int>{-3, -2, -1, 0, 1, 2, 3}));
  // Input normals turned by 2° every other column (as on a wave, not a
  // facet): no neighbor agrees within 1°, nothing is taken by this test;
  // within φ = 3° they agree again.
  Normals turning = given;
  for (int i = 0; i < P.rows(); ++i)
    if (i % 2) turning.row(i) = Eigen::RowVector3d(0.0, std::sin(0.035), std::cos(0.035));
  EXPECT_EQ(run(0.5 * lambda, turning, p).still, 0u);
  KeepInputNormalsParams wide = p;
  wide.still_uniform_deg = 3.0;
  EXPECT_GT(run(0.5 * lambda, turning, wide).still, 0u);
}

// Facets found past their edges: a flat grid (spacing 0.1, x and y in
// [-1, 1]) folded by 20° at x = 0.05 into two facets, A (x <= 0, z = 0,
// normal +z) and B (x >= 0.1), with exact input normals; every point moved
// by 0.5 λ; output normals rounded across the fold, tilted about y by 20° ·
// clamp((x + 0.15) / 0.4, 0, 1). At x = 0 and x = 0.1 the 8 nearest
// neighbors reach the other facet (3 of them, 0.017-0.018 off the tangent
// plane: a mean of 0.0064-0.0068 against e λ = 0.0005), so the plain tests
// fail; the facet test finds each one's facet among its 24 nearest (14
// members in its plane, spread in both directions, the other 10 20° off) and takes the
// input normal there: tilted 7.5° from the output normal, by the test where
// the surface stayed (the output normals within ρ turn by 10° towards the
// other facet). Not with K = 0, nor once the move exceeds μ λ; not where
// the other facet's normals are 2° off (a gradual turn, more than t of
// them), unless t allows them; not on a facet one column wide (its members
// lie on one line).
TEST(KeepInputNormals, FacetsAreFoundPastTheirEdges) {
  constexpr int side = FoldedGrid::side;
  constexpr double fold = FoldedGrid::kFold;
  const double lambda = 0.01;
  const FoldedGrid grid;
  const Positions& P = grid.P;
  const Neighborhoods& R = grid.R;
  const Normals& given = grid.given;
  const Normals& output = grid.output;
  const auto run = [&](double move, const Normals& in, const KeepInputNormalsParams& q) {
    Positions updated = P;
    updated.col(1).array() += move;
    return keep_input_normals(P, updated, in, output, {}, R, q);
  };
  // The columns x = -1 + 0.1 c whose input normal is taken, among
  // -0.3 <= x <= 0.4, in row 10.
  const auto taken_x = [&](const KeepInputNormalsResult& r, const Normals& in) {
    return taken_tenths(r, P, in, output, 10 * side + 7, 10 * side + 14);
  };
  KeepInputNormalsParams p = params_at(0.25, lambda);
  ASSERT_EQ(p.facet_neighbors, 24);
  ASSERT_EQ(p.facet_spread, 0.1);
  ASSERT_EQ(p.facet_jump, 3.0);
  ASSERT_EQ(p.facet_transitional, 2);
  const KeepInputNormalsResult r = run(0.5 * lambda, given, p);
  EXPECT_EQ(taken_x(r, given), (std::vector<int>{-3, -2, -1, 0, 1, 2, 3, 4}));
  KeepInputNormalsParams off = p;
  off.facet_neighbors = 0;
  const KeepInputNormalsResult r_off = run(0.5 * lambda, given, off);
  EXPECT_EQ(taken_x(r_off, given), (std::vector<int>{-3, -2, -1, 2, 3, 4}));
  EXPECT_EQ(r_off.facets, 0u);
  // Every point the facet test adds is counted as such: in the rows whose
  // 24 nearest lie within the grid (2-18), columns 0 and 0.1.
  EXPECT_EQ(r.facets, r.exact - r_off.exact);
  EXPECT_GE(r.facets, 2u * 17u);
  EXPECT_EQ(taken_x(run(3.5 * lambda, given, p), given), (std::vector<int>{-3, -2, -1, 2, 3, 4}));
  // B's input normals 2° from A's instead of 20°, tilted towards an azimuth
  // that turns by 72° from row to row: to a point at the fold they turn
  // gradually and from point to point (a flank's), neither across an edge
  // nor onto one other facet, so they are not taken at the default g = 2.
  Normals gradual = given;
  for (int i = 0; i < P.rows(); ++i)
    if (P(i, 0) > 0.05) {
      const double azimuth = 72.0 * (i / side) * M_PI / 180.0, tilt = 2.0 * M_PI / 180.0;
      gradual.row(i) = Eigen::RowVector3d(std::sin(tilt) * std::cos(azimuth),
                                          std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
    }
  ASSERT_EQ(p.facet_groups, 2);
  EXPECT_EQ(run(0.5 * lambda, gradual, p).facets, 0u);
  KeepInputNormalsParams any = p;
  any.facet_transitional = 24;
  EXPECT_GT(run(0.5 * lambda, gradual, any).facets, 0u);
  // A strip facet between A and B, tilted 10° (10° from each), output
  // normals 2° from the input ones, k = 3: one column wide (x = 0), its
  // members are its own column, a line, and it is not found; three columns
  // wide, all of its points are taken (the middle one by the plain test).
  // Counted over the strip's columns in rows 2-18.
  const auto strip = [&](double half_width) {
    const double tilt = 10.0 * M_PI / 180.0, turn = 2.0 * M_PI / 180.0;
    Positions Q = P;
    Normals in(P.rows(), 3), out(P.rows(), 3);
    for (int i = 0; i < P.rows(); ++i) {
      const double x = P(i, 0);
      const double a = x < -half_width ? 0.0 : x < half_width ? tilt : fold;
      Q(i, 2) = std::tan(tilt) * (std::clamp(x, -half_width, half_width) + half_width) +
                std::tan(fold) * std::max(0.0, x - half_width);
      in.row(i) = Eigen::RowVector3d(-std::sin(a), 0.0, std::cos(a));
      out.row(i) = Eigen::RowVector3d(-std::sin(a + turn), 0.0, std::cos(a + turn));
    }
    Positions updated = Q;
    updated.col(1).array() += 0.5 * lambda;
    KeepInputNormalsParams q = p;
    q.exact_neighbors = 3;
    const KeepInputNormalsResult k =
        keep_input_normals(Q, updated, in, out, {}, radius_neighborhoods(Q, {0.3, 0}), q);
    int taken = 0;
    for (int i = 0; i < P.rows(); ++i)
      if (std::abs(P(i, 0)) < half_width && i / side >= 2 && i / side <= 18)
        taken += test::angle_deg(k.normals.row(i), in.row(i)) < 1e-9;
    return taken;
  };
  EXPECT_EQ(strip(0.05), 0);
  EXPECT_EQ(strip(0.15), 3 * 17);
}

// Shallow edges (session 36): the grid folded by 2° instead of 20° at
// x = 0.05 (positions and exact input normals alike), output normals
// rounded across it, every point moved by 0.5 λ. At the fold (x = 0 and
// 0.1) the 8 nearest neighbors reach the other facet (0.0017 off the
// tangent plane, over 0.05 λ), so the plain test fails; among the 24
// nearest, 8 input normals lie 2° off (between φ = 1° and c φ = 3°: more
// than t = 2 transitional), all of them on the one other facet, in its
// plane: taken with g >= 1 (the default 2), not with g = 0 (before session
// 36).
TEST(KeepInputNormals, ShallowEdgesAreFacets) {
  constexpr int side = FoldedGrid::side;
  const double lambda = 0.01;
  const FoldedGrid grid(2.0 * M_PI / 180.0);
  Positions updated = grid.P;
  updated.col(1).array() += 0.5 * lambda;
  const auto taken_x = [&](int groups) {
    KeepInputNormalsParams q = params_at(0.25, lambda);
    q.facet_groups = groups;
    const KeepInputNormalsResult r =
        keep_input_normals(grid.P, updated, grid.given, grid.output, {}, grid.R, q);
    return taken_tenths(r, grid.P, grid.given, grid.output, 10 * side + 7, 10 * side + 14);
  };
  ASSERT_EQ(KeepInputNormalsParams{}.facet_groups, 2);
  const std::vector<int> all{-3, -2, -1, 0, 1, 2, 3, 4};
  EXPECT_EQ(taken_x(2), all);
  EXPECT_EQ(taken_x(1), all);
  EXPECT_EQ(taken_x(0), (std::vector<int>{-3, -2, -1, 2, 3, 4}));
  // That the other facet must lie in its own normal's plane is what keeps
  // normals alternating by 2° over one plane out (the "turning" normals of
  // ExactInputNormalsAreTakenWhereTheSurfaceStayed and
  // TexturePointsTakeAFacetsNormal: one other direction, but not a facet).
}

// Small facets (session 28): the flat grid z = 0 (normal +z, spacing 0.1)
// with a plate of 2 x 3 points (x in {0, 0.1}, y in {0, 0.1, 0.2}) tilted
// by 15° about the line x = 0.05, z = 0, as the small facets of a low-poly
// model; exact input normals, output normals 2° off them, every point moved
// by 0.5 λ. The plate's 8 nearest neighbors reach the grid (0.013-0.05 off
// its plane), so the plain test fails; among its 24 nearest its facet has
// 5 members, in its plane and spread in both directions, the other 19
// normals 15° off (a jump): taken with m = 4 (the default) or 5, not with
// m = 6 nor m = 8 (before session 28).
TEST(KeepInputNormals, SmallFacetsAreFound) {
  constexpr int side = 21;
  const double lambda = 0.01, tilt = 15.0 * M_PI / 180.0, turn = 2.0 * M_PI / 180.0;
  Positions P(side * side, 3);
  Normals in(side * side, 3), out(side * side, 3);
  std::vector<int> plate;
  for (int i = 0; i < P.rows(); ++i) {
    const int cx = i % side - 10, cy = i / side - 10;
    const double x = 0.1 * cx, y = 0.1 * cy;
    const bool on_plate = (cx == 0 || cx == 1) && cy >= 0 && cy <= 2;
    const double a = on_plate ? tilt : 0.0;
    P.row(i) = Eigen::RowVector3d(x, y, on_plate ? std::tan(tilt) * (x - 0.05) : 0.0);
    in.row(i) = Eigen::RowVector3d(-std::sin(a), 0.0, std::cos(a));
    out.row(i) = Eigen::RowVector3d(-std::sin(a + turn), 0.0, std::cos(a + turn));
    if (on_plate) plate.push_back(i);
  }
  ASSERT_EQ(plate.size(), 6u);
  const Neighborhoods R = radius_neighborhoods(P, {0.3, 0});
  Positions updated = P;
  updated.col(1).array() += 0.5 * lambda;
  const auto plate_taken = [&](int members) {
    KeepInputNormalsParams q = params_at(0.25, lambda);
    q.facet_members = members;
    const KeepInputNormalsResult r = keep_input_normals(P, updated, in, out, {}, R, q);
    int taken = 0;
    for (int i : plate) taken += test::angle_deg(r.normals.row(i), in.row(i)) < 1e-9;
    EXPECT_GE(r.facets, static_cast<std::size_t>(taken)) << "m = " << members;
    return taken;
  };
  ASSERT_EQ(KeepInputNormalsParams{}.facet_members, 4);
  EXPECT_EQ(plate_taken(4), 6);
  EXPECT_EQ(plate_taken(5), 6);
  EXPECT_EQ(plate_taken(6), 0);
  EXPECT_EQ(plate_taken(8), 0);
}

// Texture-labelled facets: the grid of the test above, every point
// labelled texture. Moved by 0.5 λ, the same columns are taken as for
// surface points (the input normals are exact and agree), all counted as
// texture; with texture_facets false, none. Where nothing moved, a surface
// point takes its input normal by the move everywhere, a texture point
// only by the exactness tests (the same 13 columns). With input normals
// turned 2° every other column, the 4° test takes the surface points whose
// normal is +z (even columns, an exact plane) within |x| <= 0.2, but no
// texture point: their neighbors' input normals disagree.
TEST(KeepInputNormals, TexturePointsTakeAFacetsNormal) {
  constexpr int side = RoundedGrid::side;
  const double lambda = 0.01;
  const RoundedGrid grid;
  const Positions& P = grid.P;
  const Neighborhoods& R = grid.R;
  const Normals& given = grid.given;
  const Normals& output = grid.output;
  const std::vector<std::uint8_t> texture(P.rows(), 1), surface(P.rows(), 0);
  const auto run = [&](double move, const Normals& in, const std::vector<std::uint8_t>& labels,
                       const KeepInputNormalsParams& q) {
    Positions updated = P;
    updated.col(0).array() += move;
    return keep_input_normals(P, updated, in, output, labels, R, q);
  };
  const auto taken_x = [&](const KeepInputNormalsResult& r, const Normals& in) {
    return taken_tenths(r, P, in, output, 10 * side, 10 * side + side - 1);
  };
  const std::vector<int> thirteen{-6, -5, -4, -3, -2, -1, 0, 1, 2, 3, 4, 5, 6};
  KeepInputNormalsParams p = params_at(0.25, lambda);
  ASSERT_TRUE(p.texture_facets);
  const KeepInputNormalsResult r = run(0.5 * lambda, given, texture, p);
  EXPECT_EQ(taken_x(r, given), thirteen);
  EXPECT_EQ(r.texture, r.exact);
  EXPECT_EQ(r.texture, 13u * side);
  EXPECT_EQ(taken_x(run(0.5 * lambda, given, surface, p), given), thirteen);
  KeepInputNormalsParams off = p;
  off.texture_facets = false;
  EXPECT_EQ(run(0.5 * lambda, given, texture, off).kept, 0u);
  EXPECT_EQ(run(0.0, given, surface, p).kept, static_cast<std::size_t>(P.rows()));
  EXPECT_EQ(taken_x(run(0.0, given, texture, p), given), thirteen);
  Normals turning = given;
  for (int i = 0; i < P.rows(); ++i)
    if (i % 2) turning.row(i) = Eigen::RowVector3d(0.0, std::sin(0.035), std::cos(0.035));
  EXPECT_EQ(taken_x(run(0.5 * lambda, turning, surface, p), turning), (std::vector<int>{-2, 0, 2}));
  EXPECT_EQ(run(0.5 * lambda, turning, texture, p).kept, 0u);
}

// The reach against the cone: a flat wall z = y tan 8° (spacing 0.1, x and
// y in [-1, 1]) with exact input normals tilted 8° about x, on a surface
// whose output normals turn about y by 50° x (as on a curved base, along
// the wall): every point moved by 0.5 λ. At x the tilt is
// acos(cos 50° x cos 8°), at least 8°, and no output normal lies closer to
// ñ than 8° (cos 50° x' cos 8° <= cos 8°), more than half of any tilt under
// 16°; past |x| = 0.4 the tilt exceeds θ_s = 20°. So the reach takes none.
// The cone takes x = 0 and ±0.1, whose tilts (8°, 9.4°) are within the 10°
// the output normals turn within ρ (±0.2 in x), in every row; at ±0.2 the
// tilt is 12.8°.
TEST(KeepInputNormals, TheReachTurnsAwayAWallOnACurvedBase) {
  constexpr int side = 21;
  const double lambda = 0.01;
  const double wall = 8.0 * M_PI / 180.0;
  const auto s = test::bumpy_plane(side, 0.0, 1.0);
  Positions P = s.P;
  Normals given(P.rows(), 3), output(P.rows(), 3);
  for (int i = 0; i < P.rows(); ++i) {
    const double x = -1.0 + 0.1 * (i % side), y = -1.0 + 0.1 * (i / side);
    P.row(i) = Eigen::RowVector3d(x, y, y * std::tan(wall));
    given.row(i) = Eigen::RowVector3d(0.0, -std::sin(wall), std::cos(wall));
    const double b = 50.0 * x * M_PI / 180.0;
    output.row(i) = Eigen::RowVector3d(std::sin(b), 0.0, std::cos(b));
  }
  const Neighborhoods R = radius_neighborhoods(P, {0.3, 0});
  Positions updated = P;
  updated.col(0).array() += 0.5 * lambda;
  KeepInputNormalsParams p = params_at(0.25, lambda);
  const KeepInputNormalsResult r = keep_input_normals(P, updated, given, output, {}, R, p);
  EXPECT_TRUE(taken_tenths(r, P, given, output, 10 * side, 10 * side + side - 1).empty());
  EXPECT_EQ(r.kept, 0u);
  KeepInputNormalsParams cone = p;
  cone.still_reach = 0.0;
  const KeepInputNormalsResult c = keep_input_normals(P, updated, given, output, {}, R, cone);
  EXPECT_EQ(taken_tenths(c, P, given, output, 10 * side, 10 * side + side - 1),
            (std::vector<int>{-1, 0, 1}));
  EXPECT_EQ(c.still, 3u * side);
}

// The facet's move: the fold above, where B's points from x = 0.2 on moved
// by 3.5 λ, past μ λ = 3 λ (relief beside the facets, taken down), and the
// rest by 0.5 λ.
// A's column x = 0 has B's x = 0.2 within ρ (0.21 away), so the largest
// move there exceeds μ λ; none of its facet within ρ (A's points, 1° or
// less from its normal) moved by as much, so its input normal is taken, as
// before the move (tilt 7.5°, and A's x = -0.1 has an output normal 2.5°
// from it, within half of that). B's x = 0.1 is not: its own facet's
// x = 0.2 moved. B's x = 0.2 to 0.4 are taken by the 4° test (tilts of
// 2.5° and less), whatever moved. Without the facet's move, x = 0 is not
// taken.
TEST(KeepInputNormals, AFacetBesideReliefThatMovedStayed) {
  constexpr int side = FoldedGrid::side;
  const double lambda = 0.01;
  const FoldedGrid grid;
  const Positions& P = grid.P;
  const Neighborhoods& R = grid.R;
  const Normals& given = grid.given;
  const Normals& output = grid.output;
  Positions updated = P;
  for (int i = 0; i < P.rows(); ++i) updated(i, 1) += (P(i, 0) > 0.15 ? 3.5 : 0.5) * lambda;
  KeepInputNormalsParams p = params_at(0.25, lambda);
  ASSERT_TRUE(p.still_facet_move);
  const auto taken_x = [&](const KeepInputNormalsParams& q) {
    const KeepInputNormalsResult r = keep_input_normals(P, updated, given, output, {}, R, q);
    return taken_tenths(r, P, given, output, 10 * side + 7, 10 * side + 14);
  };
  EXPECT_EQ(taken_x(p), (std::vector<int>{-3, -2, -1, 0, 2, 3, 4}));
  KeepInputNormalsParams ball = p;
  ball.still_facet_move = false;
  EXPECT_EQ(taken_x(ball), (std::vector<int>{-3, -2, -1, 2, 3, 4}));
}

// Normals the output reaches: the rounded grid above, every point moved by
// 3.5 λ (past μ λ: the surface did not stay), so the earlier tests take
// +z only within θ = 4° (|x| <= 0.2, 2° at most). After them, x = ±0.3
// (4.5°) is taken: x = ±0.1 within ρ = 0.25 has +z now, within α_r = 0.15
// of the tilt. So is x = ±0.4 (8°), through x = ±0.2, taken before: the
// fitted normal there (2°) is not within 1.2°. x = ±0.5 (12.5°) is not:
// within ρ it has x = ±0.3 at 4.5° before the reach, and ±0.4 at 8°, not
// within 1.875°. θ_r bounds the tilt (4.6°: x = ±0.3 alone); off, nothing
// more. Not where no output normal nears the input's: the same input
// normals under output normals tilted by 15° everywhere (a groove wall or
// a wave's flank under the base the update left: nothing reaches +z).
// Texture points as well, but not without texture_facets; none where the
// relief reads as sparse engraving, unless reached_engraved.
TEST(KeepInputNormals, NormalsTheOutputReachesAreTaken) {
  constexpr int side = RoundedGrid::side;
  const RoundedGrid grid;
  KeepInputNormalsParams p;
  p.radius = 0.25;
  p.lambda = 0.01;
  Positions updated = grid.P;
  updated.col(0).array() += 3.5 * p.lambda;
  ASSERT_EQ(p.reached_angle_deg, 30.0);
  ASSERT_EQ(p.reached_share, 0.15);
  const auto run = [&](const Normals& in, const Normals& output,
                       const std::vector<std::uint8_t>& texture, const KeepInputNormalsParams& q) {
    return keep_input_normals(grid.P, updated, in, output, texture, grid.R, q);
  };
  const auto taken_x = [&](const KeepInputNormalsResult& r, const Normals& output) {
    return taken_tenths(r, grid.P, grid.given, output, 10 * side, 10 * side + side - 1);
  };
  const KeepInputNormalsResult r = run(grid.given, grid.output, {}, p);
  EXPECT_EQ(taken_x(r, grid.output), (std::vector<int>{-4, -3, -2, -1, 0, 1, 2, 3, 4}));
  EXPECT_EQ(r.reached, 4u * side);
  EXPECT_EQ(r.kept, r.exact + r.reached);
  KeepInputNormalsParams narrow = p;
  narrow.reached_angle_deg = 4.6;
  EXPECT_EQ(taken_x(run(grid.given, grid.output, {}, narrow), grid.output),
            (std::vector<int>{-3, -2, -1, 0, 1, 2, 3}));
  KeepInputNormalsParams off = p;
  off.reached_angle_deg = 0.0;
  const KeepInputNormalsResult none = run(grid.given, grid.output, {}, off);
  EXPECT_EQ(taken_x(none, grid.output), (std::vector<int>{-2, -1, 0, 1, 2}));
  EXPECT_EQ(none.reached, 0u);
  // Output normals that nowhere near the input's.
  Normals tilted(grid.P.rows(), 3);
  const double t = 15.0 * M_PI / 180.0;
  tilted.rowwise() = Eigen::RowVector3d(std::sin(t), 0.0, std::cos(t));
  EXPECT_EQ(run(grid.given, tilted, {}, p).kept, 0u);
  const std::vector<std::uint8_t> texture(grid.P.rows(), 1);
  EXPECT_EQ(run(grid.given, grid.output, texture, p).reached, 4u * side);
  KeepInputNormalsParams surface_only = p;
  surface_only.texture_facets = false;
  EXPECT_EQ(run(grid.given, grid.output, texture, surface_only).kept, 0u);
  KeepInputNormalsParams engraved = p;
  engraved.engraved = true;
  EXPECT_FALSE(engraved.reached_engraved);
  EXPECT_EQ(run(grid.given, grid.output, {}, engraved).reached, 0u);
  engraved.reached_engraved = true;
  EXPECT_EQ(run(grid.given, grid.output, {}, engraved).reached, 4u * side);
}

TEST(KeepInputNormals, BadInputIsRefused) {
  const auto s = test::bumpy_plane(5, 0.0, 1.0);
  const Neighborhoods R = radius_neighborhoods(s.P, {0.3, 0});
  KeepInputNormalsParams p = params_at(0.2, 0.01);
  EXPECT_NO_THROW(keep_input_normals(s.P, s.P, s.N, s.N, {}, R, p));
  p.low = 0.3;
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N, s.N, {}, R, p), std::invalid_argument);
  p.low = -0.1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.high = -1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.high = std::nan("");
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.0);
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.0, 0.01);
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.exact_angle_deg = 90.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.exact_angle_deg = -1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.exact_residual = -0.01;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.exact_neighbors = 2;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.still_angle_deg = 90.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.still_angle_deg = -1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.still_move = -0.5;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.still_move = std::numeric_limits<double>::infinity();
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.still_move_engraved = -0.5;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.still_uniform_deg = 90.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.facet_neighbors = -1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.facet_neighbors = 0;
  EXPECT_NO_THROW(validate(p));
  p.facet_neighbors = 7;  // reads exact_neighbors (8)
  EXPECT_NO_THROW(validate(p));
  p = params_at(0.2, 0.01);
  p.facet_groups = -1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.facet_groups = kMaxFacetGroups + 1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.facet_groups = kMaxFacetGroups;
  EXPECT_NO_THROW(validate(p));
  p.facet_groups = 0;
  EXPECT_NO_THROW(validate(p));
  p = params_at(0.2, 0.01);
  p.facet_members = 2;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.facet_members = 3;
  EXPECT_NO_THROW(validate(p));
  p = params_at(0.2, 0.01);
  p.facet_spread = 0.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.facet_spread = 1.5;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.facet_jump = 0.5;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.facet_transitional = -1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = params_at(0.2, 0.01);
  p.still_reach = 1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.still_reach = -0.1;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.still_reach = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.still_reach = 0.0;  // the cone
  EXPECT_NO_THROW(validate(p));
  p.reached_angle_deg = 90.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.reached_angle_deg = -1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.reached_angle_deg = 0.0;  // off
  EXPECT_NO_THROW(validate(p));
  p.reached_share = 0.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.reached_share = 1.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.reached_share = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validate(p), std::invalid_argument);
  p.reached_share = 0.5;
  EXPECT_NO_THROW(validate(p));
  p = params_at(0.2, 0.01);
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N.topRows(3), s.N, {}, R, p), std::invalid_argument);
  EXPECT_THROW(keep_input_normals(s.P, s.P, s.N, s.N, std::vector<std::uint8_t>(2, 0), R, p),
               std::invalid_argument);
}

// Through remove_texture: synth's cube with bumps keeps the input normals
// away from its bumps and, being noise free, its exact ones within 4° of
// the fit, which changes the output normals only and brings them closer to
// the true ones, step by step; keep_input high 0, exact_angle_deg 0 and
// still_angle_deg 0 restore the output before (the fit and its blend alone). With noise of
// 0.3 λ in the positions (and the normals estimated from them), hardly
// any input normal is exact: at most 0.1% of the output normals change
// (2 of 6000 here: 8 neighbors that lie near the plane fitted to them by
// chance), and by less than 4°. The update fits the filtered normals
// throughout (update_input_normals off), so that the tests' switches change
// the output normals alone.
TEST(KeepInputNormals, RemoveTextureKeepsThemWhereTheSurfaceStayed) {
  SynthParams cp;
  cp.points = 6000;
  cp.ground_truth_points = 20000;
  const SynthesizedShape cube = synthesize_shape(cp);
  RemoveTextureParams p;
  p.threads = 2;
  p.update_input_normals = false;
  const RemoveTextureResult kept = remove_texture(cube.positions, cube.normals, p);
  p.keep_input.exact_angle_deg = 0.0;
  p.keep_input.still_angle_deg = 0.0;
  p.keep_input.reached_angle_deg = 0.0;
  const RemoveTextureResult by_move = remove_texture(cube.positions, cube.normals, p);
  p.keep_input.high = 0.0;
  const RemoveTextureResult fitted = remove_texture(cube.positions, cube.normals, p);
  EXPECT_TRUE(kept.positions == fitted.positions);
  EXPECT_TRUE(by_move.positions == fitted.positions);
  EXPECT_FALSE(kept.normals == by_move.normals);
  EXPECT_FALSE(by_move.normals == fitted.normals);
  EXPECT_GT(kept.report.input_normals_kept, by_move.report.input_normals_kept);
  EXPECT_GT(by_move.report.input_normals_kept, 0u);
  EXPECT_EQ(fitted.report.input_normals_kept, 0u);
  const auto error = [&](const RemoveTextureResult& r) {
    return compare_to_ground_truth(r.positions, r.normals, cube.ground_truth_positions,
                                   cube.ground_truth_normals)
        .mean_angle_degrees;
  };
  EXPECT_LT(error(kept), error(by_move));
  EXPECT_LT(error(by_move), error(fitted));

  cp.noise = 0.3 * kept.report.lambda / kept.report.diagonal;
  const SynthesizedShape noisy = synthesize_shape(cp);
  p = RemoveTextureParams();
  p.threads = 2;
  p.update_input_normals = false;
  const RemoveTextureResult noisy_all = remove_texture(noisy.positions, Normals(), p);
  p.keep_input.still_angle_deg = 0.0;
  const RemoveTextureResult noisy_kept = remove_texture(noisy.positions, Normals(), p);
  p.keep_input.exact_angle_deg = 0.0;
  const RemoveTextureResult noisy_by_move = remove_texture(noisy.positions, Normals(), p);
  // Where the surface stayed: the same, at most 0.1% changed.
  int still_changed = 0;
  for (int i = 0; i < noisy.positions.rows(); ++i)
    still_changed += noisy_all.normals.row(i) != noisy_kept.normals.row(i);
  EXPECT_LE(still_changed, noisy.positions.rows() / 1000);
  int changed = 0;
  for (int i = 0; i < noisy.positions.rows(); ++i) {
    if (noisy_kept.normals.row(i) == noisy_by_move.normals.row(i)) continue;
    ++changed;
    EXPECT_LT(test::angle_deg(noisy_kept.normals.row(i), noisy_by_move.normals.row(i)), 4.0);
  }
  EXPECT_LE(changed, noisy.positions.rows() / 1000);
}

}  // namespace
}  // namespace detexture
