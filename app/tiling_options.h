// The command line's tiling options (--tile, --halo, --temp-dir, --mpi) and
// the tiled runs they start: a thin layer over detexture/tiling.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "detexture/io/point_cloud.h"
#include "detexture/pipeline/remove_texture.h"
#include "detexture/tiling/remove_texture_out_of_core.h"
#include "detexture/tiling/remove_texture_tiled.h"

namespace detexture::app {

struct TilingOptions {
  TilingParams params;
  bool tile_given = false;  ///< --tile SIZE or --tile auto
  std::string temp_dir;     ///< --temp-dir: out of core
  bool mpi = false;         ///< --mpi
  bool memory_limit_given = false;
  /// Tiled in memory: --tile given, or --memory-limit given (tiles only when
  /// the whole cloud would not fit it; one tile is the plain run).
  bool in_memory_tiled() const {
    return temp_dir.empty() && !mpi && (tile_given || memory_limit_given);
  }
  bool out_of_core() const { return !temp_dir.empty() || mpi; }
};

void add_tiling_options(CLI::App& app, TilingOptions& options);

/// remove_texture, or remove_texture_tiled when the options ask for tiles and
/// the plan has more than one; per-tile lines on stderr unless quiet.
/// *tiles_json receives the "tiling" and "tiles" entries of --stats (empty
/// for a plain run).
RemoveTextureResult run_maybe_tiled(Positions P, Normals normals, const RemoveTextureParams& params,
                                    const TilingOptions& options, const PipelineObserver& observer,
                                    bool quiet, std::string* tiles_json);

/// The out-of-core run (--temp-dir; --mpi when built with MPI), printing
/// per-tile lines unless quiet.
OutOfCoreReport run_out_of_core(const std::string& input, const std::string& output,
                                const RemoveTextureParams& params, const TilingOptions& options,
                                bool quiet);

/// The "tiling" and "tiles" entries of --stats, each line ending in ",\n".
std::string tiles_json(const TiledRunReport& report);

/// The tiled observer printing "tile k/N ..." lines on stderr.
TiledRunObserver tile_printer(bool quiet);

}  // namespace detexture::app
