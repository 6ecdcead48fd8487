#include "detexture/geometry/limit_neighborhoods_to_mesh.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>
#include <vector>

namespace detexture {

void validate(const LimitNeighborhoodsToMeshParams& p) {
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("limit_neighborhoods_to_mesh: the radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.path_factor == 0.0 || (p.path_factor >= 1.0 && std::isfinite(p.path_factor))))
    throw std::invalid_argument(
        "the mesh path limit must be 0 (none) or at least 1 (a multiple of r), got " +
        number_text(p.path_factor));
}

LimitNeighborhoodsToMeshResult limit_neighborhoods_to_mesh(
    Neighborhoods& R, const Positions& P, const TriangleIndices& T,
    const LimitNeighborhoodsToMeshParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument(
        "limit_neighborhoods_to_mesh: positions and neighborhoods differ in size");
  LimitNeighborhoodsToMeshResult out;
  if (params.path_factor == 0.0) return out;

  // The edge graph, as compressed rows of (vertex, length); each edge of a
  // triangle once per direction (an edge shared by two triangles twice,
  // which Dijkstra does not mind).
  std::vector<std::uint64_t> start(n + 1, 0);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = T(t, k);
      if (a < 0 || static_cast<std::size_t>(a) >= n)
        throw std::invalid_argument("limit_neighborhoods_to_mesh: triangle " + std::to_string(t) +
                                    " refers to vertex " + std::to_string(a) + ", but there are " +
                                    std::to_string(n));
      start[static_cast<std::size_t>(a) + 1] += 2;
    }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<std::pair<std::uint32_t, double>> edges(start[n]);
  {
    std::vector<std::uint64_t> fill(start.begin(), start.end() - 1);
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      for (int k = 0; k < 3; ++k) {
        const auto a = static_cast<std::uint32_t>(T(t, k));
        const auto b = static_cast<std::uint32_t>(T(t, (k + 1) % 3));
        const double len = (P.row(a) - P.row(b)).norm();
        edges[fill[a]++] = {b, len};
        edges[fill[b]++] = {a, len};
      }
  }

  const double limit = params.path_factor * params.radius;
  constexpr double kFar = std::numeric_limits<double>::infinity();
  // reached[e] for entry e of R: p_j within the path limit of p_i.
  std::vector<std::uint8_t> reached(R.indices.size(), 0);
  std::size_t cut = 0;
#pragma omp parallel reduction(+ : cut)
  {
    // dist[v] for the members v of R_i (kFar until reached); others are not
    // entered: a path leaves the ball of R_i only to come back, which on a
    // surface sampled finer than r it does not need.
    std::vector<double> dist(n, -1.0);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) dist[*it] = kFar;
      dist[i] = 0.0;
      queue.emplace(0.0, static_cast<std::uint32_t>(i));
      while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > dist[v]) continue;
        for (std::uint64_t e = start[v]; e < start[v + 1]; ++e) {
          const double nd = d + edges[e].second;
          const std::uint32_t w = edges[e].first;
          if (nd <= limit && nd < dist[w]) {
            dist[w] = nd;
            queue.emplace(nd, w);
          }
        }
      }
      bool lost = false;
      for (std::uint64_t e = R.offsets[i]; e < R.offsets[i + 1]; ++e) {
        reached[e] = dist[R.indices[e]] != kFar;
        lost |= !reached[e];
      }
      cut += lost;
      for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) dist[*it] = -1.0;
      dist[i] = -1.0;
    }
  }
  out.points = cut;
  if (cut == 0) return out;
  // keep_neighbors visits the entries in order, so a running index is entry e.
  std::uint64_t entry = 0;
  out.removed =
      keep_neighbors(R, [&](std::size_t, std::uint32_t) { return reached[entry++] != 0; });
  return out;
}

}  // namespace detexture
