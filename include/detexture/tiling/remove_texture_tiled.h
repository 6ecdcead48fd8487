// remove_texture on a cloud held in memory, tile by tile (plan_tiles.h,
// run_tile.h): the peak memory is that of the largest tile plus the cloud
// itself, instead of the whole cloud's neighborhoods.
#pragma once

#include <string>
#include <vector>

#include "detexture/tiling/plan_tiled_run.h"
#include "detexture/tiling/run_tile.h"

namespace detexture {

/// One line of the per-tile log.
struct TileLogEntry {
  std::size_t tile = 0;            ///< index in the plan
  Eigen::Vector3i cell{0, 0, 0};   ///< grid cell
  std::size_t core_points = 0;     ///< points whose results the tile gave
  std::size_t points = 0;          ///< core and halo points it ran on
  std::size_t texture_points = 0;  ///< among the core points
  int rolling_iterations = 0;
  int update_iterations = 0;
  double seconds = 0.0;
  int rank = 0;  ///< MPI rank that ran it (0 without MPI)
};

struct TiledRunReport {
  double tile_size = 0.0, halo = 0.0;
  Eigen::Vector3i grid{1, 1, 1};
  std::size_t tiles_run = 0;  ///< tiles holding core points (empty tiles are skipped)
  std::string tile_size_reason;
  double bytes_per_point = 0.0;  ///< estimated, per tile point
  std::vector<TileLogEntry> tiles;
};

/// Observer of a tiled run: tile_begin/tile_end around each tile (tile k of
/// `count` run so far, 0-based), progress over the whole run as a fraction
/// of the points, warnings from the tiles (each once, with the first tile
/// that raised it).
struct TiledRunObserver {
  std::function<void(std::size_t k, std::size_t count, const Tile& tile, std::size_t points)>
      tile_begin;
  std::function<void(std::size_t k, std::size_t count, const TileLogEntry& entry)> tile_end;
  std::function<void(double fraction)> progress;
  std::function<void(const std::string& message)> warning;
};

/// Add a tile's report into the run's, after `merged_core` core points of
/// earlier tiles: counts summed, stage seconds summed by stage, iterations
/// and the move limit the largest, the mean neighbor count weighted by core
/// points. ransac_mean_iterations is left summed over core points (the
/// caller divides by the total).
void merge_tile_report(const TileResult& tile, std::size_t merged_core, RemoveTextureReport* run);

/// A whole-run report from the plan, before any tile: the resolved lengths.
RemoveTextureReport tiled_run_report(const TiledRunPlan& run);

/// remove_texture(P, normals, params) tile by tile. The result holds every
/// field of RemoveTextureResult in the input's order; report fields are
/// summed or maximised over the tiles (see merge_tile_report). Throws what
/// remove_texture and plan_tiled_run throw; a failing tile throws
/// std::runtime_error naming the tile and the reason.
RemoveTextureResult remove_texture_tiled(Positions P, Normals normals,
                                         const RemoveTextureParams& params,
                                         const TilingParams& tiling,
                                         const TiledRunObserver& observer = {},
                                         TiledRunReport* report = nullptr);

}  // namespace detexture
