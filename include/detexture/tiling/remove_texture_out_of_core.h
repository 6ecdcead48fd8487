// remove_texture on a binary PLY file larger than memory: a first pass finds
// the bounding box and keeps an even sample (to plan the tiles), a second
// bins the points to tiles on temporary files, then the tiles are run one by
// one (run_tile.h) and their core results written straight to their place in
// the output, so that it is in the input's order. Peak memory: the largest
// tile's run, plus the sample.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "detexture/io/ply_stream.h"
#include "detexture/tiling/remove_texture_tiled.h"
#include "detexture/tiling/tile_bins.h"

namespace detexture {

struct OutOfCoreParams {
  std::string temp_dir;              ///< parent of the temporary folder; must exist
  std::size_t max_sample = 1000000;  ///< points kept by the first pass to plan the tiles
};

/// What the first pass learns about the input.
struct PlyScan {
  Box bounds;
  std::uint64_t points = 0;
  Positions sample;        ///< every `stride`-th point
  Normals sample_normals;  ///< their normals (0 rows without)
  std::uint64_t stride = 1;
  double seconds = 0.0;
};

/// First pass: bounds and sample. Throws std::runtime_error for bad files.
PlyScan scan_ply(PlyVertexReader& reader, std::size_t max_sample, const std::string& path);

/// The tiled run's plan from a scan (plan_tiled_run on the sample), with the
/// out-of-core driver's own memory per tile point (its records and index
/// lists) counted in the budget.
TiledRunPlan plan_out_of_core(const PlyScan& scan, const RemoveTextureParams& params,
                              const TilingParams& tiling, std::size_t record_size);

/// Run tile t from its bin: the core results, encoded in `out` layout, go to
/// sink(input index, record) in the order of the bin (input order).
TileLogEntry run_binned_tile(const TileBins& bins, std::size_t t, const TilePlan& plan,
                             const PlyVertexLayout& in, const PlyVertexLayout& out,
                             const RemoveTextureParams& tile_params,
                             const std::function<void(const std::string&)>& warning,
                             const std::function<void(std::uint64_t, const unsigned char*)>& sink,
                             RemoveTextureReport* merged, std::size_t merged_core);

struct OutOfCoreReport {
  std::uint64_t points = 0;
  bool had_normals = false;
  RemoveTextureReport report;  ///< merged over the tiles (merge_tile_report)
  TiledRunReport tiles;
  double scan_seconds = 0.0, bin_seconds = 0.0, tiles_seconds = 0.0;
  bool root = true;  ///< false on MPI ranks other than 0: they print and write nothing
};

/// The whole out-of-core run from `input` to `output` (written through an
/// OutputFile: nothing appears at `output` unless every tile succeeded).
/// Observer as for remove_texture_tiled; its progress covers the scan and bin
/// passes (first 10%) and the tiles. Throws std::runtime_error for files,
/// std::invalid_argument for parameters, ResourceLimitError for the budget;
/// a failing tile throws naming the tile.
OutOfCoreReport remove_texture_out_of_core(const std::string& input, const std::string& output,
                                           const RemoveTextureParams& params,
                                           const TilingParams& tiling, const OutOfCoreParams& ooc,
                                           const TiledRunObserver& observer = {});

/// Extra bytes per tile point the out-of-core driver holds besides
/// remove_texture's own (records, index, positions, normals, results).
double out_of_core_bytes_per_point(std::size_t record_size);

}  // namespace detexture
