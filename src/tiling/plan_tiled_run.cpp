#include "detexture/tiling/plan_tiled_run.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/pipeline/estimate_texture_scale.h"

namespace detexture {

TiledRunPlan plan_tiled_run(const Positions& sample, const Normals& sample_normals, double weight,
                            const Box& bounds, std::size_t total_points,
                            const RemoveTextureParams& params, const TilingParams& tiling) {
  validate(params);
  if (sample.rows() == 0) throw std::invalid_argument("the point cloud is empty");
  if (!(weight >= 1.0)) throw std::invalid_argument("plan_tiled_run: a sample weight is ≥ 1");
  TiledRunPlan run;
  TileLengths& L = run.lengths;
  L.diagonal = (bounds.hi - bounds.lo).norm();
  if (!(L.diagonal > 0.0))
    throw std::invalid_argument("all points coincide: the cloud has no extent to filter");
  if (params.radius.unit == Length::Unit::Texture) {
    if (weight != 1.0)
      throw std::invalid_argument(
          "an out-of-core run cannot estimate the texture radius (it needs the cloud at full "
          "density); give -r, e.g. from 'detexture PART --scale-report' on a piece of the cloud");
    L.scale = estimate_texture_scale(sample, sample_normals, params.scale);
    L.scale_estimated = true;
  }
  L.radius = choose_radius(params, L.diagonal, L.scale);
  const double r = L.radius.radius;
  run.tile_params = resolve_tile_params(params, L);

  // remove_texture's neighborhood-share guard, on the whole cloud.
  double count = estimate_neighbor_count(sample, r) * weight;
  if (params.max_neighbors > 0) count = std::min(count, double(params.max_neighbors));
  const double share = count / static_cast<double>(total_points);
  if (!params.allow_large_radius &&
      (share > params.max_neighbor_share || count > params.max_mean_neighbors))
    throw std::invalid_argument(
        "r = " + number_text(r) + " would put about " + number_text(std::round(count)) +
        " points (" + number_text(std::round(100.0 * share)) +
        "% of the cloud) in every neighborhood; memory and time grow as r², and a neighborhood "
        "that large filters the shape itself. Choose a smaller r, or force the run (--force on "
        "the command line)");

  const NeighborhoodsMemoryEstimate e =
      estimate_neighborhoods_memory(sample, {r, params.max_neighbors}, 256);
  run.mean_neighbors = std::max(1.0, e.mean_neighbors * weight);
  if (params.max_neighbors > 0)
    run.mean_neighbors = std::min(run.mean_neighbors, double(params.max_neighbors));
  run.bytes_per_point =
      kBytesPerPoint + 4.0 * 1.05 * run.mean_neighbors + tiling.extra_bytes_per_point;

  const double halo = tiling.halo.resolve(L.diagonal, r);
  if (!(halo >= 0.0) || !std::isfinite(halo))
    throw std::invalid_argument("the tile halo must be a length of zero or more");
  double size = tiling.tile_size.resolve(L.diagonal, r);
  if (tiling.tile_size.unit == Length::Unit::Texture)
    throw std::invalid_argument("the tile size cannot be a multiple of the texture radius");
  if (size > 0.0) {
    run.tile_size_reason = "given as " + to_string(tiling.tile_size);
  } else {
    std::uint64_t budget = tiling.memory_budget != 0 ? tiling.memory_budget : params.memory_limit;
    if (budget == 0) budget = default_memory_limit();
    if (budget == 0 || budget == std::numeric_limits<std::uint64_t>::max())
      throw std::invalid_argument("an automatic tile size needs a memory budget (--memory-limit)");
    const double left = static_cast<double>(budget) - tiling.reserved_bytes;
    if (!(left > 0.0))
      throw ResourceLimitError(
          "the memory limit of " + memory_size_text(static_cast<double>(budget)) +
          " does not even hold the cloud itself (" + memory_size_text(tiling.reserved_bytes) +
          "); raise --memory-limit or run out of core (--temp-dir)");
    run.max_tile_points = left / run.bytes_per_point;
    const PointHistogram h = point_histogram(sample, bounds, weight);
    size = choose_tile_size(h, halo, run.max_tile_points);
    run.tile_size_reason = "largest fitting " + memory_size_text(left) + " per tile (about " +
                           number_text(std::round(run.max_tile_points)) + " points at " +
                           number_text(std::round(run.bytes_per_point)) + " B/point)";
  }
  run.plan = plan_tiles(bounds, size, halo);
  return run;
}

}  // namespace detexture
