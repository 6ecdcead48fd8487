// Everything a tiled run decides before its first tile: the lengths resolved
// against the whole cloud, the halo, the tile size (given, or the largest that
// fits a memory budget) and the tiles.
#pragma once

#include <cstdint>
#include <string>

#include "detexture/pipeline/remove_texture.h"
#include "detexture/tiling/plan_tiles.h"
#include "detexture/tiling/resolve_tile_params.h"

namespace detexture {

struct TilingParams {
  /// Edge of a tile's core cube ("2.5", "0.1d", "60r"); value 0 = choose the
  /// largest size whose tiles fit `memory_budget`.
  Length tile_size{0.0, Length::Unit::Absolute};
  /// Halo added on every side of a core (tile_halo.h): 4r by default, a
  /// measured trade-off; the exact cone is 34r for the local updates.
  Length halo{4.0, Length::Unit::Radius};
  /// Bytes one tile may use (its points, neighborhoods and results), when
  /// the tile size is chosen automatically; 0 = RemoveTextureParams::memory_limit
  /// or, if that is 0 too, default_memory_limit().
  std::uint64_t memory_budget = 0;
  /// Bytes the caller holds for the whole cloud meanwhile, taken off the
  /// budget (the in-memory driver's copy of the cloud and its results).
  double reserved_bytes = 0.0;
  /// Bytes the caller holds per tile point besides remove_texture's own
  /// (the out-of-core driver's records and results).
  double extra_bytes_per_point = 0.0;
};

struct TiledRunPlan {
  TileLengths lengths;
  RemoveTextureParams tile_params;  ///< absolute lengths, shared by every tile
  TilePlan plan;
  double mean_neighbors = 0.0;   ///< estimated |R_i|
  double bytes_per_point = 0.0;  ///< estimated peak of remove_texture per point
  double max_tile_points = 0.0;  ///< the budget in points (automatic size only)
  std::string tile_size_reason;  ///< "given as ..." or "largest fitting ..."
};

/// Plan a tiled run on a cloud of `total_points` points with bounding box
/// `bounds`, from `sample`: the whole cloud (weight 1, in spatial order when r
/// is estimated, as remove_texture estimates it) or an even subsample of it
/// whose rows each stand for `weight` points. r as a multiple of the texture
/// radius needs the whole cloud (the estimate reads the local density);
/// with a subsample it throws std::invalid_argument asking for -r. The
/// neighborhood-share guard of remove_texture is checked here, on the whole
/// cloud, and off in the tiles. Throws std::invalid_argument for bad
/// parameters and ResourceLimitError when no tile fits the budget.
TiledRunPlan plan_tiled_run(const Positions& sample, const Normals& sample_normals, double weight,
                            const Box& bounds, std::size_t total_points,
                            const RemoveTextureParams& params, const TilingParams& tiling);

}  // namespace detexture
