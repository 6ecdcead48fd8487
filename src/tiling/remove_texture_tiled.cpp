#include "detexture/tiling/remove_texture_tiled.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/geometry/spatial_order.h"

namespace detexture {

RemoveTextureReport tiled_run_report(const TiledRunPlan& run) {
  RemoveTextureReport r;
  r.diagonal = run.lengths.diagonal;
  r.radius_choice = run.lengths.radius.choice;
  r.radius_reason = run.lengths.radius.reason;
  r.scale_estimated = run.lengths.scale_estimated;
  r.scale = run.lengths.scale;
  const RemoveTextureParams& p = run.tile_params;
  r.radius = p.radius.value;
  r.lambda = p.lambda.value;
  r.sigma_s = p.sigma_s.value;
  r.sigma_p = p.sigma_p.value;
  r.neighbors.min = std::numeric_limits<std::size_t>::max();
  return r;
}

void merge_tile_report(const TileResult& tile, std::size_t merged_core, RemoveTextureReport* run) {
  const RemoveTextureReport& t = tile.report;
  RemoveTextureReport& r = *run;
  const double core = static_cast<double>(tile.core.size());
  // Means weighted by core points; the neighbor statistics are those of the
  // tile's run (core and halo).
  const double before = static_cast<double>(merged_core);
  r.neighbors.mean = (r.neighbors.mean * before + t.neighbors.mean * core) / (before + core);
  r.neighbors.min = std::min(r.neighbors.min, t.neighbors.min);
  r.neighbors.max = std::max(r.neighbors.max, t.neighbors.max);
  r.neighbors.sparse_points += t.neighbors.sparse_points;
  r.normals_estimated = r.normals_estimated || t.normals_estimated;
  r.normals_ignored = r.normals_ignored || t.normals_ignored;
  r.normals_reestimated += t.normals_reestimated;
  r.normals_degenerate += t.normals_degenerate;
  r.normals_flipped += t.normals_flipped;
  r.opposite_neighbors += t.opposite_neighbors;
  r.surface_split_neighbors += t.surface_split_neighbors;
  for (const std::uint8_t x : tile.is_texture) r.texture_points += x;
  r.no_plane += t.no_plane;
  r.ransac_mean_iterations += t.ransac_mean_iterations * core;  // divided by the caller
  r.empty_subneighborhoods += t.empty_subneighborhoods;
  r.rolling_iterations = std::max(r.rolling_iterations, t.rolling_iterations);
  r.update_isolated += t.update_isolated;
  r.update_iterations = std::max(r.update_iterations, t.update_iterations);
  r.texture_height = std::max(r.texture_height, t.texture_height);
  r.max_move = std::max(r.max_move, t.max_move);
  r.moves_limited += t.moves_limited;
  r.relief_lean += t.relief_lean * core;  // divided by the caller
  r.counter_moves_limited += t.counter_moves_limited;
  r.tip_moves_limited += t.tip_moves_limited;
  r.sink_moves_limited += t.sink_moves_limited;
  r.raised_cells_lowered += t.raised_cells_lowered;
  r.raised_cells_limited += t.raised_cells_limited;
  r.raised_cells_turned += t.raised_cells_turned;
  r.normals_not_fitted += t.normals_not_fitted;
  r.normals_blended += t.normals_blended;
  r.input_normals_kept += t.input_normals_kept;
  r.input_normals_updated += t.input_normals_updated;
  r.waves_flagged += t.waves_flagged;
  r.waves_released += t.waves_released;
  r.duplicates_merged += t.duplicates_merged;
  r.estimated_bytes = std::max(r.estimated_bytes, t.estimated_bytes);
  for (const StageTiming& s : t.timings) {
    auto it = std::find_if(r.timings.begin(), r.timings.end(),
                           [&s](const StageTiming& x) { return x.stage == s.stage; });
    if (it == r.timings.end())
      r.timings.push_back(s);
    else
      it->seconds += s.seconds;
  }
  r.mean_displacement = 0.0;  // set by the caller from the assembled result
}

RemoveTextureResult remove_texture_tiled(Positions P, Normals normals,
                                         const RemoveTextureParams& params,
                                         const TilingParams& tiling,
                                         const TiledRunObserver& observer, TiledRunReport* report) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (n == 0) throw std::invalid_argument("the point cloud is empty");
  if (normals.rows() != 0 && normals.rows() != P.rows())
    throw std::invalid_argument("there must be as many normals as points, or none");
  const Box bounds = bounding_box(P);
  TilingParams t = tiling;
  // Held meanwhile: the input (positions, normals) and the assembled result
  // (positions, normals, input normals, height, label) and the tile lists.
  t.reserved_bytes += static_cast<double>(n) * (5 * 24 + 8 + 1 + 8);
  TiledRunPlan run;
  if (params.radius.unit == Length::Unit::Texture) {
    // As remove_texture does: the estimate reads the points in spatial order.
    const std::vector<std::uint32_t> order = spatial_order(P);
    const Positions OP = permute_rows(P, order);
    const Normals ON = normals.rows() != 0 ? permute_rows(normals, order) : Normals();
    run = plan_tiled_run(OP, ON, 1.0, bounds, n, params, t);
  } else {
    run = plan_tiled_run(P, Normals(), 1.0, bounds, n, params, t);
  }
  const TilePlan& plan = run.plan;

  // Tile membership, as CSR over tiles: a first pass counts, a second fills.
  const std::size_t tiles = plan.tiles.size();
  std::vector<std::size_t> offsets(tiles + 1, 0), cores(tiles, 0);
  std::vector<std::size_t> of;
  for (std::size_t i = 0; i < n; ++i) {
    tiles_of_point(plan, P.row(static_cast<Eigen::Index>(i)).transpose(), &of);
    for (const std::size_t k : of) ++offsets[k + 1];
    ++cores[core_tile(plan, P.row(static_cast<Eigen::Index>(i)).transpose())];
  }
  for (std::size_t k = 0; k < tiles; ++k) offsets[k + 1] += offsets[k];
  std::vector<std::uint32_t> members(offsets[tiles]);
  {
    std::vector<std::size_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      tiles_of_point(plan, P.row(static_cast<Eigen::Index>(i)).transpose(), &of);
      for (const std::size_t k : of) members[fill[k]++] = static_cast<std::uint32_t>(i);
    }
  }
  std::size_t count = 0;
  for (std::size_t k = 0; k < tiles; ++k) count += cores[k] > 0;

  RemoveTextureResult result;
  result.positions.resize(P.rows(), 3);
  result.normals.resize(P.rows(), 3);
  result.input_normals.resize(P.rows(), 3);
  result.is_texture.assign(n, 0);
  result.texture_height.resize(P.rows());
  result.report = tiled_run_report(run);
  TiledRunReport log;
  log.tile_size = plan.tile_size;
  log.halo = plan.halo;
  log.grid = plan.grid;
  log.tiles_run = count;
  log.tile_size_reason = run.tile_size_reason;
  log.bytes_per_point = run.bytes_per_point;
  std::set<std::string> warned;
  std::size_t done = 0, k_run = 0;
  for (std::size_t k = 0; k < tiles; ++k) {
    if (cores[k] == 0) continue;
    const Tile& tile = plan.tiles[k];
    const std::size_t m = offsets[k + 1] - offsets[k];
    const std::uint32_t* rows = members.data() + offsets[k];
    if (observer.tile_begin) observer.tile_begin(k_run, count, tile, m);
    Positions TP(static_cast<Eigen::Index>(m), 3);
    Normals TN(normals.rows() != 0 ? static_cast<Eigen::Index>(m) : 0, 3);
    std::vector<std::uint8_t> is_core(m);
    for (std::size_t s = 0; s < m; ++s) {
      TP.row(static_cast<Eigen::Index>(s)) = P.row(rows[s]);
      if (TN.rows() != 0) TN.row(static_cast<Eigen::Index>(s)) = normals.row(rows[s]);
      is_core[s] = core_tile(plan, TP.row(static_cast<Eigen::Index>(s)).transpose()) == k;
    }
    PipelineObserver inner;
    inner.warning = [&](const std::string& message) {
      if (warned.insert(message).second && observer.warning)
        observer.warning("tile " + std::to_string(k) + ": " + message);
    };
    TileResult tr;
    try {
      tr = run_tile(std::move(TP), std::move(TN), is_core, run.tile_params, inner);
    } catch (...) {
      rethrow_tile_failure(k, m, false);
    }
    for (std::size_t c = 0; c < tr.core.size(); ++c) {
      const Eigen::Index i = rows[tr.core[c]];
      const auto ci = static_cast<Eigen::Index>(c);
      result.positions.row(i) = tr.positions.row(ci);
      result.normals.row(i) = tr.normals.row(ci);
      result.input_normals.row(i) = tr.input_normals.row(ci);
      result.is_texture[static_cast<std::size_t>(i)] = tr.is_texture[c];
      result.texture_height(i) = tr.texture_height(ci);
    }
    merge_tile_report(tr, done, &result.report);
    TileLogEntry e;
    e.tile = k;
    e.cell = tile.cell;
    e.core_points = tr.core.size();
    e.points = m;
    for (const std::uint8_t x : tr.is_texture) e.texture_points += x;
    e.rolling_iterations = tr.report.rolling_iterations;
    e.update_iterations = tr.report.update_iterations;
    e.seconds = tr.seconds;
    log.tiles.push_back(e);
    done += tr.core.size();
    if (observer.tile_end) observer.tile_end(k_run, count, e);
    if (observer.progress) observer.progress(static_cast<double>(done) / static_cast<double>(n));
    ++k_run;
  }
  RemoveTextureReport& r = result.report;
  r.ransac_mean_iterations /= static_cast<double>(n);
  r.relief_lean /= static_cast<double>(n);
  r.mean_displacement = (result.positions - P).rowwise().norm().mean();
  result.input_positions = std::move(P);
  if (result.input_normals.rows() == 0) result.input_normals = Normals();
  if (report) *report = std::move(log);
  return result;
}

}  // namespace detexture
