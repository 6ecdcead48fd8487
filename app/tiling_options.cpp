#include "tiling_options.h"

#include <unistd.h>

#include <cstdio>
#include <limits>

#include "detexture/geometry/spatial_order.h"
#include "detexture/tiling/remove_texture_mpi.h"

namespace detexture::app {

void add_tiling_options(CLI::App& app, TilingOptions& o) {
  app.add_option_function<std::string>(
         "--tile",
         [&o](const std::string& text) {
           o.tile_given = true;
           if (text == "auto") {
             o.params.tile_size = {0.0, Length::Unit::Absolute};
             return;
           }
           try {
             o.params.tile_size = parse_length(text);
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError("--tile", e.what());
           }
           if (o.params.tile_size.unit == Length::Unit::Texture)
             throw CLI::ValidationError("--tile",
                                        "give the tile size in the cloud's units, of "
                                        "the diagonal (0.1d) or of r (60r), or auto");
         },
         "Process the cloud in cubes of this edge (a LENGTH: 2.5, 0.1d, 60r), each with a halo, "
         "keeping each cube's own results; 'auto' chooses the largest size fitting "
         "--memory-limit. Results differ from the whole-cloud run by a measured bound (README, "
         "Large clouds and clusters)")
      ->type_name("SIZE");
  app.add_option_function<std::string>(
         "--halo",
         [&o](const std::string& text) {
           try {
             o.params.halo = parse_length(text);
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError("--halo", e.what());
           }
           if (o.params.halo.unit == Length::Unit::Texture)
             throw CLI::ValidationError("--halo", "give the halo in the cloud's units or of r");
         },
         "Width added around each tile (tiled runs) [default: " + to_string(o.params.halo) + "]")
      ->type_name("LENGTH");
  app.add_option("--temp-dir", o.temp_dir,
                 "Out of core: bin the points to tiles in temporary files in this folder "
                 "(removed at exit, on errors and on signals), then process the tiles one by one; "
                 "binary PLY in and out. Implies tiles (--tile auto unless given)");
  app.add_flag("--mpi", o.mpi,
               "Spread the tiles over the ranks of mpirun (rank 0 reads and writes; needs "
               "--temp-dir on storage all ranks share)");
}

std::string tiles_json(const TiledRunReport& t) {
  std::string json;
  char line[512];
  std::snprintf(line, sizeof line,
                "  \"tiling\": {\"tile_size\": %.17g, \"halo\": %.17g, \"grid\": [%d, %d, %d], "
                "\"tiles_run\": %zu, \"bytes_per_point\": %.6g, \"tile_size_reason\": \"%s\"},\n",
                t.tile_size, t.halo, t.grid(0), t.grid(1), t.grid(2), t.tiles_run,
                t.bytes_per_point, t.tile_size_reason.c_str());
  json += line;
  json += "  \"tiles\": [";
  for (std::size_t k = 0; k < t.tiles.size(); ++k) {
    const TileLogEntry& e = t.tiles[k];
    std::snprintf(line, sizeof line,
                  "%s\n    {\"tile\": %zu, \"cell\": [%d, %d, %d], \"core_points\": %zu, "
                  "\"points\": %zu, \"texture_points\": %zu, \"rolling_iterations\": %d, "
                  "\"update_iterations\": %d, \"seconds\": %.6f, \"rank\": %d}",
                  k ? "," : "", e.tile, e.cell(0), e.cell(1), e.cell(2), e.core_points, e.points,
                  e.texture_points, e.rolling_iterations, e.update_iterations, e.seconds, e.rank);
    json += line;
  }
  json += "\n  ],\n";
  return json;
}

TiledRunObserver tile_printer(bool quiet) {
  TiledRunObserver o;
  if (quiet) return o;
  o.tile_begin = [](std::size_t k, std::size_t count, const Tile& tile, std::size_t points) {
    if (k == 0) std::fprintf(stderr, "  %zu tiles to run\n", count);
    (void)tile;
    (void)points;
  };
  o.tile_end = [](std::size_t k, std::size_t count, const TileLogEntry& e) {
    std::fprintf(stderr,
                 "  tile %zu/%zu (cell %d,%d,%d): %zu points, %zu with halo, %.2f s (%.0f%% of "
                 "tiles done)\n",
                 k + 1, count, e.cell(0), e.cell(1), e.cell(2), e.core_points, e.points, e.seconds,
                 100.0 * double(k + 1) / double(count));
  };
  o.warning = [](const std::string& message) {
    std::fprintf(stderr, "detexture: warning: %s\n", message.c_str());
  };
  return o;
}

RemoveTextureResult run_maybe_tiled(Positions P, Normals normals, const RemoveTextureParams& params,
                                    const TilingOptions& options, const PipelineObserver& observer,
                                    bool quiet, std::string* json) {
  json->clear();
  if (!options.in_memory_tiled())
    return remove_texture(std::move(P), std::move(normals), params, observer);
  if (!options.tile_given) {
    // --memory-limit alone: tiles only when the whole cloud does not fit and
    // tiles do; otherwise the plain run, whose memory guard refuses with its
    // own message when the cloud does not fit.
    if (params.memory_limit == std::numeric_limits<std::uint64_t>::max())
      return remove_texture(std::move(P), std::move(normals), params, observer);
    const std::size_t n = static_cast<std::size_t>(P.rows());
    if (n == 0) throw std::invalid_argument("the point cloud is empty");
    TilingParams t = options.params;
    t.reserved_bytes = static_cast<double>(n) * (5 * 24 + 17);
    TiledRunPlan plan;
    const Box bounds = bounding_box(P);
    try {
      if (params.radius.unit == Length::Unit::Texture) {
        const std::vector<std::uint32_t> order = spatial_order(P);
        plan = plan_tiled_run(permute_rows(P, order),
                              normals.rows() ? permute_rows(normals, order) : Normals(), 1.0,
                              bounds, n, params, t);
      } else {
        plan = plan_tiled_run(P, Normals(), 1.0, bounds, n, params, t);
      }
    } catch (const ResourceLimitError&) {
      return remove_texture(std::move(P), std::move(normals), params, observer);
    } catch (const std::invalid_argument&) {
      return remove_texture(std::move(P), std::move(normals), params, observer);
    }
    if (plan.plan.tiles.size() == 1)
      return remove_texture(std::move(P), std::move(normals), params, observer);
    if (!quiet)
      std::fprintf(stderr, "the whole cloud would exceed --memory-limit: running in tiles\n");
  }
  TiledRunReport report;
  RemoveTextureResult r = remove_texture_tiled(std::move(P), std::move(normals), params,
                                               options.params, tile_printer(quiet), &report);
  if (!quiet)
    std::fprintf(stderr, "tiles: %d x %d x %d grid of size %g (%s), halo %g; %zu run\n",
                 report.grid(0), report.grid(1), report.grid(2), report.tile_size,
                 report.tile_size_reason.c_str(), report.halo, report.tiles_run);
  *json = tiles_json(report);
  return r;
}

namespace {

// The closing line of an out-of-core run on stderr.
void print_out_of_core_summary(const OutOfCoreReport& r) {
  std::fprintf(stderr,
               "tiles: %d x %d x %d grid of size %g (%s), halo %g; scan %.1f s, bin %.1f s, "
               "tiles %.1f s\n",
               r.tiles.grid(0), r.tiles.grid(1), r.tiles.grid(2), r.tiles.tile_size,
               r.tiles.tile_size_reason.c_str(), r.tiles.halo, r.scan_seconds, r.bin_seconds,
               r.tiles_seconds);
}

}  // namespace

OutOfCoreReport run_out_of_core(const std::string& input, const std::string& output,
                                const RemoveTextureParams& params, const TilingOptions& options,
                                bool quiet) {
#ifndef DETEXTURE_HAVE_MPI
  if (options.mpi)
    throw std::invalid_argument(
        "--mpi is not available: this detexture was built without MPI (install "
        "libopenmpi-dev and rebuild)");
#endif
  OutOfCoreParams ooc;
  ooc.temp_dir = options.temp_dir.empty() ? "." : options.temp_dir;
#ifdef DETEXTURE_HAVE_MPI
  if (options.mpi) {
    static MpiSession session;  // finalized at exit, after the outputs are written
    const bool root = session.rank() == 0;
    TiledRunObserver observer = tile_printer(quiet || !root);
    if (!quiet && root)
      observer.tile_begin = [&session](std::size_t k, std::size_t count, const Tile&, std::size_t) {
        if (k == 0)
          std::fprintf(stderr,
                       "  scanned and binned the input; rank 0 runs %zu tiles of %d ranks\n", count,
                       session.size());
      };
    OutOfCoreReport r =
        remove_texture_mpi(session, input, output, params, options.params, ooc, observer);
    r.root = root;
    if (!quiet && root) print_out_of_core_summary(r);
    return r;
  }
#endif
  TiledRunObserver observer = tile_printer(quiet);
  if (!quiet)
    observer.tile_begin = [](std::size_t k, std::size_t count, const Tile&, std::size_t) {
      if (k == 0) std::fprintf(stderr, "  scanned and binned the input; %zu tiles to run\n", count);
    };
  const OutOfCoreReport r =
      remove_texture_out_of_core(input, output, params, options.params, ooc, observer);
  if (!quiet) print_out_of_core_summary(r);
  return r;
}

}  // namespace detexture::app
