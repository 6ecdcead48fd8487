// One tile of a tiled run: remove_texture on the tile's core and halo points,
// keeping the results of the core points only. The in-memory, out-of-core
// and MPI drivers all call this.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/pipeline/remove_texture.h"

namespace detexture {

struct TileResult {
  std::vector<std::uint32_t> core;       ///< rows of the tile's input that are core, increasing
  Positions positions;                   ///< #core by 3, texture removed
  Normals normals;                       ///< #core by 3 filtered normals
  Normals input_normals;                 ///< #core by 3, the normals the filters started from
  std::vector<std::uint8_t> is_texture;  ///< #core
  Eigen::VectorXd texture_height;        ///< #core
  RemoveTextureReport report;            ///< of the run on core and halo
  double seconds = 0.0;                  ///< wall time of the run
};

/// Run remove_texture on a tile's points P (#T by 3: core and halo) with
/// normals (#T by 3, or 0 rows), and keep the rows where is_core is non-zero.
/// `params` must have absolute lengths (resolve_tile_params). Throws what
/// remove_texture throws, and std::invalid_argument when is_core does not
/// have #T entries or marks no point.
TileResult run_tile(Positions P, Normals normals, const std::vector<std::uint8_t>& is_core,
                    const RemoveTextureParams& params, const PipelineObserver& observer = {});

/// From a catch block around run_tile: rethrows the exception being handled
/// with "tile TILE (POINTS points) failed: " before its message. A
/// ResourceLimitError or std::invalid_argument keeps its type (and so its
/// exit code); another std::exception becomes a std::runtime_error when
/// wrap_other is set and passes unchanged otherwise, as does anything else.
[[noreturn]] void rethrow_tile_failure(std::size_t tile, std::size_t points, bool wrap_other);

}  // namespace detexture
