#include "detexture/geometry/radius_neighborhoods.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
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

constexpr std::size_t kBlock = 1024;

// Runs query(i, out) for every point in parallel blocks and appends the
// per-point results in point order, so the layout does not depend on the
// number of threads. The blocks are done a small batch at a time (a few per
// thread) and appended as each batch ends, so only one batch is ever held
// twice: holding half the cloud's lists twice made this the peak of the whole
// run. The index array grows by an estimate from the points done so far, so it
// is rarely reallocated.
template <class Query>
Neighborhoods build(std::size_t n, const ProgressFn& progress, Query&& query) {
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t batch =
      std::max<std::size_t>(8, 4 * static_cast<std::size_t>(omp_get_max_threads()));
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
          const std::size_t before = out.size();
          query(i, found, out);
          result.offsets[i + 1] = out.size() - before;
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

// Appends the first `keep` of `found` to out, sorted by distance, ties by
// index, so the order is fully determined. Each key packs the squared
// distance as a float (its bits order like the numbers, since it is never
// negative) above the index. The keys are first distributed into as many
// buckets as there are keys by distance (on a surface the squared distance
// of a neighbor is close to uniform, so a bucket holds about one key), then
// an insertion sort finishes the nearly sorted list: linear time in practice,
// 4x faster than std::sort here (perf: the sort was over half of this stage).
void append_sorted(const std::vector<std::pair<std::uint32_t, double>>& found, std::size_t keep,
                   std::vector<std::uint32_t>& out) {
  thread_local std::vector<std::uint64_t> keys, sorted;
  thread_local std::vector<std::uint32_t> bucket_start;
  const std::size_t k = found.size();
  keys.resize(k);
  sorted.resize(k);
  float largest = 0.0f;
  for (std::size_t t = 0; t < k; ++t) {
    const float d = static_cast<float>(found[t].second);
    largest = std::max(largest, d);
    std::uint32_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    keys[t] = static_cast<std::uint64_t>(bits) << 32 | found[t].first;
  }
  auto bucket_of = [&](std::uint64_t key) -> std::size_t {
    const std::uint32_t bits = static_cast<std::uint32_t>(key >> 32);
    float d;
    std::memcpy(&d, &bits, sizeof d);
    // Monotone in d, so buckets are in distance order; clamped for rounding.
    const std::size_t b =
        largest > 0.0f ? static_cast<std::size_t>(d / largest * static_cast<float>(k)) : 0;
    return std::min(b, k - 1);
  };
  bucket_start.assign(k + 1, 0);
  for (std::size_t t = 0; t < k; ++t) ++bucket_start[bucket_of(keys[t]) + 1];
  for (std::size_t b = 0; b < k; ++b) bucket_start[b + 1] += bucket_start[b];
  for (std::size_t t = 0; t < k; ++t) sorted[bucket_start[bucket_of(keys[t])]++] = keys[t];
  for (std::size_t t = 1; t < k; ++t) {
    const std::uint64_t key = sorted[t];
    std::size_t s = t;
    for (; s > 0 && sorted[s - 1] > key; --s) sorted[s] = sorted[s - 1];
    sorted[s] = key;
  }
  keep = std::min(keep, k);
  for (std::size_t t = 0; t < keep; ++t) out.push_back(static_cast<std::uint32_t>(sorted[t]));
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
  std::atomic<bool> capped{false};
  Neighborhoods result =
      build(n, progress,
            [&](std::size_t i, std::vector<std::pair<std::uint32_t, double>>& found,
                std::vector<std::uint32_t>& out) {
              const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
              index.within(q, params.radius, found);
              if (found.size() > cap) capped.store(true, std::memory_order_relaxed);
              append_sorted(found, cap, out);
            });
  // The distance test is symmetric (the same sum of the same squares), so
  // only a cap can make it one-sided.
  result.symmetric = !capped.load();
  return result;
}

Neighborhoods knn_neighborhoods(const Positions& P, int k, const ProgressFn& progress) {
  if (k < 1) throw std::invalid_argument("k for nearest neighbors must be at least 1");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const std::size_t kk = std::min<std::size_t>(static_cast<std::size_t>(k), n);
  const PointIndex index(P);
  return build(n, progress,
               [&](std::size_t i, std::vector<std::pair<std::uint32_t, double>>& found,
                   std::vector<std::uint32_t>& out) {
                 const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
                 thread_local std::vector<std::uint32_t> idx;
                 thread_local std::vector<double> dist;
                 index.nearest(q, kk, idx, dist);
                 found.clear();
                 for (std::size_t t = 0; t < idx.size(); ++t) found.emplace_back(idx[t], dist[t]);
                 append_sorted(found, found.size(), out);
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
