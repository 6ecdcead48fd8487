// Tiled processing (detexture/tiling): the plan cuts the cloud as worked out by
// hand, one tile is the plain run bit for bit, and tiles with halos stay close
// to the whole-cloud result.
#include <gtest/gtest.h>

#include <set>

#include "detexture/tiling/plan_tiles.h"
#include "detexture/tiling/remove_texture_tiled.h"
#include "detexture/tiling/resolve_tile_params.h"
#include "detexture/tiling/tile_halo.h"
#include "test_support.h"

namespace detexture {
namespace {

Box unit_box() {
  Box b;
  b.lo = Eigen::Vector3d::Zero();
  b.hi = Eigen::Vector3d::Ones();
  return b;
}

TEST(PlanTiles, HalvesOfTheUnitCube) {
  const TilePlan plan = plan_tiles(unit_box(), 0.5, 0.1);
  EXPECT_EQ(plan.grid, Eigen::Vector3i(2, 2, 2));
  ASSERT_EQ(plan.tiles.size(), 8u);
  EXPECT_EQ(plan.tiles[7].cell, Eigen::Vector3i(1, 1, 1));
  EXPECT_DOUBLE_EQ(plan.tiles[7].extended.lo(0), 0.4);
  EXPECT_DOUBLE_EQ(plan.tiles[0].extended.hi(2), 0.6);
  EXPECT_EQ(core_tile(plan, {0.25, 0.25, 0.25}), 0u);
  EXPECT_EQ(core_tile(plan, {0.75, 0.25, 0.25}), 1u);  // x fastest
  EXPECT_EQ(core_tile(plan, {0.25, 0.75, 0.25}), 2u);
  EXPECT_EQ(core_tile(plan, {1.0, 1.0, 1.0}), 7u);   // the upper bound belongs to the last
  EXPECT_EQ(core_tile(plan, {-5.0, 0.2, 9.0}), 4u);  // outside: clamped
  std::vector<std::size_t> of;
  tiles_of_point(plan, {0.2, 0.2, 0.2}, &of);
  EXPECT_EQ(of, std::vector<std::size_t>({0}));
  tiles_of_point(plan, {0.45, 0.2, 0.2}, &of);  // within the halo of the tile on its right
  EXPECT_EQ(of, std::vector<std::size_t>({0, 1}));
  tiles_of_point(plan, {0.55, 0.2, 0.2}, &of);  // and the other way round
  EXPECT_EQ(of, std::vector<std::size_t>({0, 1}));
  tiles_of_point(plan, {0.5, 0.5, 0.5}, &of);  // the centre is in every halo
  EXPECT_EQ(of.size(), 8u);
  EXPECT_THROW(plan_tiles(unit_box(), 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(plan_tiles(unit_box(), 0.5, -1.0), std::invalid_argument);
  EXPECT_THROW(plan_tiles(unit_box(), 1e-9, 0.0), std::invalid_argument);
}

TEST(PlanTiles, EveryPointHasOneCoreInsideItsTiles) {
  const TilePlan plan = plan_tiles(unit_box(), 0.3, 0.07);  // 4 x 4 x 4, the last sticks out
  EXPECT_EQ(plan.grid, Eigen::Vector3i(4, 4, 4));
  std::vector<std::size_t> of;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const Eigen::Vector3d p(i / 20.0, j / 20.0, (i * j % 21) / 20.0);
      tiles_of_point(plan, p, &of);
      const std::size_t core = core_tile(plan, p);
      EXPECT_TRUE(std::find(of.begin(), of.end(), core) != of.end());
      EXPECT_TRUE(plan.tiles[core].core.contains(p));
      for (const std::size_t t : of) EXPECT_TRUE(plan.tiles[t].extended.contains(p));
      // and no tile whose extended box holds p is missing
      for (const Tile& t : plan.tiles)
        if (t.extended.contains(p) && ((p - t.extended.lo).array() > 1e-12).all() &&
            ((t.extended.hi - p).array() > 1e-12).all())
          EXPECT_TRUE(std::find(of.begin(), of.end(), t.index) != of.end());
    }
}

TEST(PlanTiles, ChosenSizeFitsTheBudget) {
  // 100 x 100 points on the plane z = 0.5 of the unit cube: tiles of 0.5 hold
  // 2,500 points each, so a budget of 2,600 (halo 0) allows at most 0.5 and,
  // in steps of 1.25, no less than 0.5 / 1.25².
  Positions P(10000, 3);
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) P.row(i * 100 + j) << (i + 0.5) / 100, (j + 0.5) / 100, 0.5;
  Box b = unit_box();
  const PointHistogram h = point_histogram(P, b);
  const double size = choose_tile_size(h, 0.0, 2600.0);
  EXPECT_LE(size, 0.5 + 1e-9);
  EXPECT_GE(size, 0.5 / (1.25 * 1.25));
  const TilePlan plan = plan_tiles(b, size, 0.0);
  std::vector<int> count(plan.tiles.size(), 0);
  for (Eigen::Index i = 0; i < P.rows(); ++i) ++count[core_tile(plan, P.row(i).transpose())];
  EXPECT_LE(*std::max_element(count.begin(), count.end()), 2600);
  // Everything fits one tile when the budget holds the cloud.
  EXPECT_GE(choose_tile_size(h, 0.1, 1e9), 1.0);
  // A halo holding more than the budget cannot be tiled.
  EXPECT_THROW(choose_tile_size(h, 0.5, 100.0), ResourceLimitError);
}

RemoveTextureParams plane_params() {
  RemoveTextureParams p;
  p.radius = {0.06, Length::Unit::Absolute};
  p.lambda = {0.002, Length::Unit::Absolute};
  return p;
}

// Every length is resolved against the whole cloud (d = 2, r = 0.1 here),
// never against a tile's own diagonal.
TEST(ResolveTileParams, EveryLengthIsInTheCloudsUnits) {
  RemoveTextureParams p;
  p.lambda = {0.05, Length::Unit::Radius};
  p.sigma_s = {0.01, Length::Unit::Diagonal};
  p.fit_sigma = {0.02, Length::Unit::Diagonal};
  p.solve_radius = {0.03, Length::Unit::Absolute};
  TileLengths lengths;
  lengths.diagonal = 2.0;
  lengths.radius.radius = 0.1;
  const RemoveTextureParams t = resolve_tile_params(p, lengths);
  for (const Length& len : {t.radius, t.lambda, t.sigma_s, t.sigma_p, t.solve_radius, t.fit_sigma,
                            t.min_surface_radius})
    EXPECT_EQ(len.unit, Length::Unit::Absolute);
  EXPECT_DOUBLE_EQ(t.radius.value, 0.1);
  EXPECT_DOUBLE_EQ(t.lambda.value, 0.005);
  EXPECT_DOUBLE_EQ(t.sigma_s.value, 0.02);
  EXPECT_DOUBLE_EQ(t.fit_sigma.value, 0.04);
  EXPECT_DOUBLE_EQ(t.solve_radius.value, 0.03);
  EXPECT_DOUBLE_EQ(t.sigma_p.value, 0.05);             // 0.5r
  EXPECT_DOUBLE_EQ(t.min_surface_radius.value, 0.05);  // 0.5r
}

TEST(RemoveTextureTiled, OneTileIsThePlainRunBitForBit) {
  const auto s = test::bumpy_plane(61, 0.03, 0.015);
  RemoveTextureParams p = plane_params();
  p.lambda = {0.05, Length::Unit::Radius};  // resolved once for the tiles, the same way
  p.fit_normals = false;                    // the filtered normals first, then the default
  const RemoveTextureResult whole = remove_texture(s.P, s.N, p);
  TilingParams t;
  t.tile_size = {2.0, Length::Unit::Absolute};
  TiledRunReport report;
  const RemoveTextureResult tiled = remove_texture_tiled(s.P, s.N, p, t, {}, &report);
  EXPECT_EQ(report.tiles_run, 1u);
  EXPECT_TRUE(tiled.positions == whole.positions);
  EXPECT_TRUE(tiled.normals == whole.normals);
  EXPECT_EQ(tiled.is_texture, whole.is_texture);
  EXPECT_TRUE(tiled.input_positions == s.P);
  p.fit_normals = true;
  p.fit_sigma = {0.01, Length::Unit::Diagonal};
  p.output_normals.blend_low_deg = 0.0;  // a narrow window, so the blend mixes somewhere
  p.output_normals.blend_high_deg = 0.05;
  p.blend_share_high = 0.0;  // that window on every cloud, not the open one
  const RemoveTextureResult whole_fit = remove_texture(s.P, s.N, p);
  EXPECT_GT(whole_fit.report.normals_blended, 0u);
  const RemoveTextureResult tiled_fit = remove_texture_tiled(s.P, s.N, p, t, {}, &report);
  EXPECT_TRUE(tiled_fit.normals == whole_fit.normals);
  EXPECT_FALSE(tiled_fit.normals == tiled.normals);
}

// Two bumpy patches 3 apart (far beyond the exact reach 36r + r = 2.22 of the
// local update): with one patch per tile, each tile is exactly that patch run
// alone, whatever the halo.
TEST(RemoveTextureTiled, SeparatePatchesAreTheirOwnRunsBitForBit) {
  const auto s = test::bumpy_plane(41, 0.03, 0.015);
  const Eigen::Index n = s.P.rows();
  Positions P(2 * n, 3);
  Normals N(2 * n, 3);
  P.topRows(n) = s.P;
  N.topRows(n) = s.N;
  P.bottomRows(n) = s.P;
  P.bottomRows(n).col(0).array() += 4.0;
  N.bottomRows(n) = s.N;
  RemoveTextureParams p = plane_params();
  p.update.mode = UpdateMode::Isotropic;
  EXPECT_NEAR(exact_tile_reach(p), 37 * 0.06, 1e-12);  // blended output normals: + 2r
  RemoveTextureParams filtered = p;
  filtered.fit_normals = false;
  EXPECT_NEAR(exact_tile_reach(filtered), 35 * 0.06, 1e-12);
  p.update.mode = UpdateMode::Global;
  EXPECT_TRUE(std::isinf(exact_tile_reach(p)));
  TilingParams t;
  t.tile_size = {2.5, Length::Unit::Absolute};  // x: [0, 2.5) and [2.5, 5)
  t.halo = {1.0, Length::Unit::Absolute};
  TiledRunReport report;
  const RemoveTextureResult tiled = remove_texture_tiled(P, N, p, t, {}, &report);
  EXPECT_EQ(report.tiles_run, 2u);
  const RemoveTextureResult left = remove_texture(s.P, s.N, p);
  Positions right_in = s.P;
  right_in.col(0).array() += 4.0;
  const RemoveTextureResult right = remove_texture(right_in, s.N, p);
  EXPECT_TRUE(tiled.positions.topRows(n) == left.positions);
  EXPECT_TRUE(tiled.positions.bottomRows(n) == right.positions);
  EXPECT_TRUE(tiled.normals.bottomRows(n) == right.normals);
}

// A bump cut in four by the tile boundaries x = 0.5 and y = 0.5: with a halo
// of 4r every core point sees what it sees in the whole cloud up to 4r, and the
// result stays within a small fraction of r of the whole-cloud one.
TEST(RemoveTextureTiled, TilesThroughABumpStayCloseToTheWholeRun) {
  const auto s = test::bumpy_plane(81, 0.03, 0.015);
  const RemoveTextureParams p = plane_params();
  const RemoveTextureResult whole = remove_texture(s.P, s.N, p);
  TilingParams t;
  t.tile_size = {0.5, Length::Unit::Absolute};
  TiledRunReport report;
  const RemoveTextureResult tiled = remove_texture_tiled(s.P, s.N, p, t, {}, &report);
  EXPECT_EQ(report.tiles_run, 4u);
  EXPECT_NEAR(report.halo, 4 * 0.06, 1e-12);
  ASSERT_EQ(report.tiles.size(), 4u);
  std::size_t core = 0;
  for (const TileLogEntry& e : report.tiles) core += e.core_points;
  EXPECT_EQ(core, static_cast<std::size_t>(s.P.rows()));
  const double max_diff = (tiled.positions - whole.positions).rowwise().norm().maxCoeff();
  EXPECT_LT(max_diff, 0.02 * 0.06) << "max difference " << max_diff;
  std::size_t same_label = 0;
  for (std::size_t i = 0; i < whole.is_texture.size(); ++i)
    same_label += whole.is_texture[i] == tiled.is_texture[i];
  EXPECT_GE(same_label, whole.is_texture.size() * 99 / 100);
  // And the bump is still gone.
  EXPECT_LT(tiled.positions.col(2).cwiseAbs().maxCoeff(), 0.003);
}

// Without normals each tile estimates and orients its own: a flat tile faces
// up (orient_normals.h, rule 2), so the tiles agree with each other and with
// the whole run. Before session 11 each tile's side hung on its farthest
// point: 97% of a tiled plane's normals faced down, 3% up.
TEST(RemoveTextureTiled, TilesOfAPlaneWithoutNormalsAllFaceUp) {
  const auto s = test::bumpy_plane(81, 0.03, 0.015);
  const RemoveTextureParams p = plane_params();
  TilingParams t;
  t.tile_size = {0.5, Length::Unit::Absolute};
  TiledRunReport report;
  const RemoveTextureResult tiled = remove_texture_tiled(s.P, Normals(), p, t, {}, &report);
  EXPECT_EQ(report.tiles_run, 4u);
  EXPECT_TRUE(tiled.report.normals_estimated);
  EXPECT_GT(tiled.input_normals.col(2).minCoeff(), 0.0);
  EXPECT_GT(tiled.normals.col(2).minCoeff(), 0.0);
  const RemoveTextureResult whole = remove_texture(s.P, Normals(), p);
  EXPECT_GT(whole.normals.col(2).minCoeff(), 0.0);
}

}  // namespace
}  // namespace detexture
