#include "detexture/tiling/plan_tiles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "detexture/geometry/estimate_neighborhoods_memory.h"

namespace detexture {

Box bounding_box(const Positions& P) {
  if (P.rows() == 0) throw std::invalid_argument("the bounding box of no points is undefined");
  Box b;
  b.lo = P.colwise().minCoeff().transpose();
  b.hi = P.colwise().maxCoeff().transpose();
  return b;
}

TilePlan plan_tiles(const Box& bounds, double tile_size, double halo) {
  if (!(tile_size > 0.0) || !std::isfinite(tile_size))
    throw std::invalid_argument("the tile size must be a positive length, got " +
                                number_text(tile_size));
  if (!(halo >= 0.0) || !std::isfinite(halo))
    throw std::invalid_argument("the tile halo must be a length of zero or more, got " +
                                number_text(halo));
  TilePlan plan;
  plan.bounds = bounds;
  plan.tile_size = tile_size;
  plan.halo = halo;
  double total = 1.0;
  for (int d = 0; d < 3; ++d) {
    const double cells = std::max(1.0, std::ceil((bounds.hi(d) - bounds.lo(d)) / tile_size));
    total *= cells;
    if (!(total <= double(1 << 24)))
      throw std::invalid_argument("tiles of size " + number_text(tile_size) +
                                  " would cut the cloud into more than 2^24 tiles; give a "
                                  "larger --tile");
    plan.grid(d) = static_cast<int>(cells);
  }
  plan.tiles.resize(static_cast<std::size_t>(total));
  for (int z = 0; z < plan.grid(2); ++z)
    for (int y = 0; y < plan.grid(1); ++y)
      for (int x = 0; x < plan.grid(0); ++x) {
        const std::size_t t = (static_cast<std::size_t>(z) * plan.grid(1) + y) * plan.grid(0) + x;
        Tile& tile = plan.tiles[t];
        tile.index = t;
        tile.cell = {x, y, z};
        tile.core.lo = bounds.lo + tile_size * tile.cell.cast<double>();
        tile.core.hi = tile.core.lo + Eigen::Vector3d::Constant(tile_size);
        tile.extended.lo = tile.core.lo - Eigen::Vector3d::Constant(halo);
        tile.extended.hi = tile.core.hi + Eigen::Vector3d::Constant(halo);
      }
  return plan;
}

namespace {

int clamp_cell(double offset, double size, int cells) {
  const double c = std::floor(offset / size);
  if (!(c >= 0.0)) return 0;  // also NaN
  return c >= cells - 1 ? cells - 1 : static_cast<int>(c);
}

}  // namespace

std::size_t core_tile(const TilePlan& plan, const Eigen::Vector3d& p) {
  std::size_t t = 0;
  for (int d = 2; d >= 0; --d)
    t = t * plan.grid(d) + clamp_cell(p(d) - plan.bounds.lo(d), plan.tile_size, plan.grid(d));
  return t;
}

void tiles_of_point(const TilePlan& plan, const Eigen::Vector3d& p, std::vector<std::size_t>* out) {
  out->clear();
  int first[3], last[3];
  for (int d = 0; d < 3; ++d) {
    const double offset = p(d) - plan.bounds.lo(d);
    const int core = clamp_cell(offset, plan.tile_size, plan.grid(d));
    // The cells whose extended interval [lo - halo, hi + halo] holds p; the
    // core cell always does (its clamped interval covers p).
    first[d] = std::min(core, clamp_cell(offset - plan.halo, plan.tile_size, plan.grid(d)));
    last[d] = std::max(core, clamp_cell(offset + plan.halo, plan.tile_size, plan.grid(d)));
  }
  for (int z = first[2]; z <= last[2]; ++z)
    for (int y = first[1]; y <= last[1]; ++y)
      for (int x = first[0]; x <= last[0]; ++x)
        out->push_back((static_cast<std::size_t>(z) * plan.grid(1) + y) * plan.grid(0) + x);
}

PointHistogram point_histogram(const Positions& P, const Box& bounds, double weight,
                               int resolution) {
  if (resolution < 1 || resolution > 1024)
    throw std::invalid_argument("the histogram resolution must be in [1, 1024]");
  PointHistogram h;
  h.bounds = bounds;
  h.resolution = resolution;
  h.weight = weight;
  h.counts.assign(static_cast<std::size_t>(resolution) * resolution * resolution, 0);
  const double edge = std::max((bounds.hi - bounds.lo).maxCoeff(), 1e-300) / resolution;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    std::size_t c = 0;
    for (int d = 2; d >= 0; --d)
      c = c * resolution + clamp_cell(P(i, d) - bounds.lo(d), edge, resolution);
    ++h.counts[c];
  }
  return h;
}

double choose_tile_size(const PointHistogram& h, double halo, double max_points) {
  const int n = h.resolution;
  const double longest = std::max((h.bounds.hi - h.bounds.lo).maxCoeff(), 1e-300);
  const double edge = longest / n;
  // Summed-volume table: S(x, y, z) = counts in cells [0, x) × [0, y) × [0, z).
  const int m = n + 1;
  std::vector<double> S(static_cast<std::size_t>(m) * m * m, 0.0);
  auto at = [m](int x, int y, int z) { return (static_cast<std::size_t>(z) * m + y) * m + x; };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        S[at(x + 1, y + 1, z + 1)] = h.counts[(static_cast<std::size_t>(z) * n + y) * n + x] +
                                     S[at(x, y + 1, z + 1)] + S[at(x + 1, y, z + 1)] +
                                     S[at(x + 1, y + 1, z)] - S[at(x, y, z + 1)] -
                                     S[at(x, y + 1, z)] - S[at(x + 1, y, z)] + S[at(x, y, z)];
  auto box_count = [&](const Box& b) {
    int lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::clamp(static_cast<int>(std::floor((b.lo(d) - h.bounds.lo(d)) / edge)), 0, n);
      hi[d] = std::clamp(static_cast<int>(std::ceil((b.hi(d) - h.bounds.lo(d)) / edge)), 0, n);
      if (hi[d] == lo[d]) hi[d] = std::min(n, lo[d] + 1);
    }
    const double c = S[at(hi[0], hi[1], hi[2])] - S[at(lo[0], hi[1], hi[2])] -
                     S[at(hi[0], lo[1], hi[2])] - S[at(hi[0], hi[1], lo[2])] +
                     S[at(lo[0], lo[1], hi[2])] + S[at(lo[0], hi[1], lo[2])] +
                     S[at(hi[0], lo[1], lo[2])] - S[at(lo[0], lo[1], lo[2])];
    return c * h.weight;
  };
  double worst = 0.0;
  // From one tile holding everything down, while a tile is no smaller than
  // its halo and a histogram cell.
  for (double size = longest * 1.0000001;; size /= 1.25) {
    const TilePlan plan = plan_tiles(h.bounds, size, halo);
    worst = 0.0;
    for (const Tile& t : plan.tiles) worst = std::max(worst, box_count(t.extended));
    if (worst <= max_points) return size;
    if (size / 1.25 < halo || size / 1.25 < edge) break;
  }
  throw ResourceLimitError("no tile size fits the memory budget: tiles as small as their halo (" +
                           number_text(halo) + ") would still hold about " +
                           number_text(std::round(worst)) + " points, more than the " +
                           number_text(std::round(max_points)) +
                           " the budget allows; raise --memory-limit or use a smaller --radius");
}

}  // namespace detexture
