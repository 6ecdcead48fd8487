#include "detexture/geometry/radius_neighborhoods.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "detexture/geometry/point_index.h"
#include "progress_counter.h"

namespace detexture {
namespace {

constexpr std::size_t kBlock = 2048;

// Runs query(i, out) for every point in parallel blocks and appends the
// per-point results in point order, so the layout does not depend on the
// number of threads. The blocks are done a batch at a time and appended as
// each batch ends, so at most one batch is held twice (not the whole
// neighborhood list); the index array grows by an estimate from the points
// done so far, so it is rarely reallocated.
template <class Query>
Neighborhoods build(std::size_t n, const ProgressFn& progress, Query&& query) {
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t batch = 32;  // blocks per batch: 64k points
  std::vector<std::vector<std::uint32_t>> block_indices(std::min(batch, blocks));
  Neighborhoods result;
  result.offsets.assign(n + 1, 0);
  ProgressCounter counter(progress, n);
  for (std::size_t first = 0; first < blocks; first += batch) {
    const std::size_t last = std::min(blocks, first + batch);
#pragma omp parallel
    {
      std::vector<std::pair<std::uint32_t, double>> found;
#pragma omp for schedule(dynamic, 1)
      for (std::size_t b = first; b < last; ++b) {
        const std::size_t lo = b * kBlock, hi = std::min(n, lo + kBlock);
        auto& out = block_indices[b - first];
        out.clear();
        for (std::size_t i = lo; i < hi; ++i) {
          query(i, found);
          result.offsets[i + 1] = found.size();
          for (const auto& f : found) out.push_back(f.first);
        }
        counter.advance(hi - lo);
      }
    }
    const std::size_t lo = first * kBlock, hi = std::min(n, last * kBlock);
    for (std::size_t i = lo; i < hi; ++i) result.offsets[i + 1] += result.offsets[i];
    if (result.offsets[hi] > result.indices.capacity())
      result.indices.reserve(static_cast<std::size_t>(1.05 * result.offsets[hi] * n / hi) + 64);
    for (std::size_t b = first; b < last; ++b)
      result.indices.insert(result.indices.end(), block_indices[b - first].begin(),
                            block_indices[b - first].end());
  }
  return result;
}

// Sort by distance, ties by index, so the order is fully determined. The keys
// pack the squared distance as a float (its bits order like the numbers, since
// it is never negative) above the index: one integer sort, 3x cheaper than
// sorting the pairs.
void sort_by_distance(std::vector<std::pair<std::uint32_t, double>>& found) {
  thread_local std::vector<std::uint64_t> keys;
  keys.resize(found.size());
  for (std::size_t t = 0; t < found.size(); ++t) {
    const float d = static_cast<float>(found[t].second);
    std::uint32_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    keys[t] = static_cast<std::uint64_t>(bits) << 32 | found[t].first;
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t t = 0; t < found.size(); ++t) {
    const std::uint32_t bits = static_cast<std::uint32_t>(keys[t] >> 32);
    float d;
    std::memcpy(&d, &bits, sizeof d);
    found[t] = {static_cast<std::uint32_t>(keys[t]), static_cast<double>(d)};
  }
}

}  // namespace

Neighborhoods radius_neighborhoods(const Positions& P, const RadiusNeighborhoodsParams& params,
                                   const ProgressFn& progress) {
  if (!(params.radius > 0.0) || !std::isfinite(params.radius))
    throw std::invalid_argument("the neighborhood radius must be a positive number, got " +
                                number_text(params.radius));
  if (params.max_neighbors < 0)
    throw std::invalid_argument("the neighbor cap must be 0 (no cap) or positive");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const PointIndex index(P);
  const std::size_t cap = params.max_neighbors > 0 ? static_cast<std::size_t>(params.max_neighbors)
                                                   : std::numeric_limits<std::size_t>::max();
  return build(n, progress,
               [&](std::size_t i, std::vector<std::pair<std::uint32_t, double>>& found) {
                 const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
                 index.within(q, params.radius, found);
                 sort_by_distance(found);
                 if (found.size() > cap) found.resize(cap);
               });
}

Neighborhoods knn_neighborhoods(const Positions& P, int k, const ProgressFn& progress) {
  if (k < 1) throw std::invalid_argument("k for nearest neighbors must be at least 1");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const std::size_t kk = std::min<std::size_t>(static_cast<std::size_t>(k), n);
  const PointIndex index(P);
  return build(n, progress,
               [&](std::size_t i, std::vector<std::pair<std::uint32_t, double>>& found) {
                 const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
                 thread_local std::vector<std::uint32_t> idx;
                 thread_local std::vector<double> dist;
                 index.nearest(q, kk, idx, dist);
                 found.clear();
                 for (std::size_t t = 0; t < idx.size(); ++t) found.emplace_back(idx[t], dist[t]);
                 sort_by_distance(found);
               });
}

NeighborhoodStats neighborhood_stats(const Neighborhoods& N, std::size_t min_count) {
  NeighborhoodStats s;
  const std::size_t n = N.size();
  if (n == 0) return s;
  s.min = std::numeric_limits<std::size_t>::max();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = N.count(i);
    s.min = std::min(s.min, c);
    s.max = std::max(s.max, c);
    if (c < min_count) ++s.sparse_points;
  }
  s.mean = static_cast<double>(N.indices.size()) / static_cast<double>(n);
  return s;
}

}  // namespace detexture
