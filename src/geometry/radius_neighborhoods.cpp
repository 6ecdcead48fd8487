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

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "detexture/geometry/point_index.h"
#include "progress_counter.h"

namespace detexture {
namespace {

constexpr std::size_t kBlock = 1024;

// Runs query(i, out) for every point in parallel blocks, with one query
// object (and its scratch space) per thread from make_query(), and appends
// the per-point results in point order, so the layout does not depend on the
// number of threads. The blocks are done a small batch at a time (a few per
// thread) and appended as each batch ends, so only one batch is ever held
// twice: holding half the cloud's lists twice made this the peak of the whole
// run. The index array grows by an estimate from the points done so far, so
// it is rarely reallocated.
template <class MakeQuery>
Neighborhoods build(std::size_t n, const ProgressFn& progress, const MakeQuery& make_query) {
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  const std::size_t batch =
      std::max<std::size_t>(4, 2 * static_cast<std::size_t>(omp_get_max_threads()));
  std::vector<std::vector<std::uint32_t>> block_indices(std::min(batch, blocks));
  Neighborhoods result;
  result.offsets.assign(n + 1, 0);
  ProgressCounter counter(progress, n);
  for (std::size_t first = 0; first < blocks; first += batch) {
    const std::size_t last = std::min(blocks, first + batch);
#pragma omp parallel
    {
      auto query = make_query();
#pragma omp for schedule(dynamic, 1)
      for (std::size_t b = first; b < last; ++b) {
        const std::size_t lo = b * kBlock, hi = std::min(n, lo + kBlock);
        auto& out = block_indices[b - first];
        out.clear();
        for (std::size_t i = lo; i < hi; ++i) {
          const std::size_t before = out.size();
          query(i, out);
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

// A neighbor as one sortable integer: its squared distance as a float (the
// bits of a non-negative float order like the numbers) above its index, so
// that sorting the keys orders by distance, ties by index.
std::uint64_t neighbor_key(double distance_sq, std::uint32_t index) {
  const float d = static_cast<float>(distance_sq);
  std::uint32_t bits;
  std::memcpy(&bits, &d, sizeof bits);
  return static_cast<std::uint64_t>(bits) << 32 | index;
}

float key_distance(std::uint64_t key) {
  const std::uint32_t bits = static_cast<std::uint32_t>(key >> 32);
  float d;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

// Sorts the keys and appends the indices of the first `keep` to out. The
// keys are first distributed into as many buckets as there are keys by
// distance (on a surface the squared distance of a neighbor is close to
// uniform, so a bucket holds about one key), then an insertion sort finishes
// the nearly sorted list: linear time in practice. perf had std::sort at over
// half of this stage; with this the stage went from 0.71 to 0.52 s on
// bench/speed's 150k sphere, with the same order.
class NeighborSorter {
 public:
  void append(const std::vector<std::uint64_t>& keys, std::size_t keep,
              std::vector<std::uint32_t>& out) {
    const std::size_t k = keys.size();
    if (k == 0) return;
    float largest = 0.0f;
    for (const std::uint64_t key : keys) largest = std::max(largest, key_distance(key));
    // d * scale is monotone in d, so the buckets are in distance order.
    const float scale = largest > 0.0f ? static_cast<float>(k) / largest : 0.0f;
    bucket_.resize(k);
    start_.assign(k + 1, 0);
    for (std::size_t t = 0; t < k; ++t) {
      const std::size_t b = static_cast<std::size_t>(key_distance(keys[t]) * scale);
      bucket_[t] = static_cast<std::uint32_t>(std::min(b, k - 1));
      ++start_[bucket_[t] + 1];
    }
    for (std::size_t b = 0; b < k; ++b) start_[b + 1] += start_[b];
    sorted_.resize(k);
    for (std::size_t t = 0; t < k; ++t) sorted_[start_[bucket_[t]]++] = keys[t];
    // Many keys in one bucket (near-duplicate points, one far neighbor) would
    // make the insertion sort quadratic: past 8 moves per key on average,
    // std::sort finishes instead. The order is the same (keys are distinct).
    std::size_t moves = 0;
    const std::size_t max_moves = 8 * k + 64;
    for (std::size_t t = 1; t < k; ++t) {
      const std::uint64_t key = sorted_[t];
      std::size_t s = t;
      for (; s > 0 && sorted_[s - 1] > key; --s) sorted_[s] = sorted_[s - 1];
      sorted_[s] = key;
      moves += t - s;
      if (moves > max_moves) {
        std::sort(sorted_.begin(), sorted_.end());
        break;
      }
    }
    keep = std::min(keep, k);
    for (std::size_t t = 0; t < keep; ++t) out.push_back(static_cast<std::uint32_t>(sorted_[t]));
  }

 private:
  std::vector<std::uint32_t> bucket_, start_;
  std::vector<std::uint64_t> sorted_;
};

}  // namespace

Neighborhoods radius_neighborhoods(const Positions& P, const RadiusNeighborhoodsParams& params,
                                   const ProgressFn& progress) {
  if (!(params.radius > 0.0) || !std::isfinite(params.radius))
    throw std::invalid_argument("the neighborhood radius must be a positive number, got " +
                                number_text(params.radius));
  if (params.max_neighbors < 0)
    throw std::invalid_argument("the neighbor cap must be 0 (no cap) or positive");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const std::size_t cap = params.max_neighbors > 0 ? static_cast<std::size_t>(params.max_neighbors)
                                                   : std::numeric_limits<std::size_t>::max();
  std::atomic<bool> capped{false};
  const PointIndex index(P);
  Neighborhoods result = build(n, progress, [&] {
    return [&, found = std::vector<std::pair<std::uint32_t, double>>(),
            keys = std::vector<std::uint64_t>(),
            sorter = NeighborSorter()](std::size_t i, std::vector<std::uint32_t>& out) mutable {
      const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
      index.within(q, params.radius, found);
      keys.resize(found.size());
      for (std::size_t t = 0; t < found.size(); ++t)
        keys[t] = neighbor_key(found[t].second, found[t].first);
      if (keys.size() > cap) capped.store(true, std::memory_order_relaxed);
      sorter.append(keys, cap, out);
    };
  });
  // The distance test is symmetric (the same sum of the same squares), so
  // only a cap can make it one-sided.
  result.symmetric = !capped.load();
  return result;
}

namespace {

// Returns the whole pages between size() and capacity() to the system. The
// vector keeps its capacity (the pages come back zeroed if it ever grows), so
// no second copy is ever held, as shrink_to_fit would need for a moment.
void release_unused_capacity(std::vector<std::uint32_t>& v) {
#if defined(__linux__)
  const std::uintptr_t page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t first = reinterpret_cast<std::uintptr_t>(v.data() + v.size());
  const std::uintptr_t last = reinterpret_cast<std::uintptr_t>(v.data() + v.capacity());
  const std::uintptr_t begin = (first + page - 1) / page * page, end = last / page * page;
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_DONTNEED);
#else
  v.shrink_to_fit();
#endif
}

}  // namespace

void shrink_neighborhoods(Neighborhoods& R, const Positions& P, double radius) {
  if (!(radius >= 0.0)) throw std::invalid_argument("shrink_neighborhoods: negative radius");
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument("shrink_neighborhoods: positions and neighborhoods differ in size");
  const double radius_sq = radius * radius;
  std::uint64_t write = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t begin = R.offsets[i], end = R.offsets[i + 1];
    R.offsets[i] = write;
    for (std::uint64_t e = begin; e < end; ++e) {
      const std::uint32_t j = R.indices[e];
      if ((P.row(j) - P.row(i)).squaredNorm() > radius_sq) break;
      R.indices[write++] = j;
    }
  }
  R.offsets[n] = write;
  R.indices.resize(write);
  release_unused_capacity(R.indices);
}

Neighborhoods knn_neighborhoods(const Positions& P, int k, const ProgressFn& progress) {
  if (k < 1) throw std::invalid_argument("k for nearest neighbors must be at least 1");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const std::size_t kk = std::min<std::size_t>(static_cast<std::size_t>(k), n);
  const PointIndex index(P);
  return build(n, progress, [&] {
    return [&, idx = std::vector<std::uint32_t>(), dist = std::vector<double>(),
            keys = std::vector<std::uint64_t>(),
            sorter = NeighborSorter()](std::size_t i, std::vector<std::uint32_t>& out) mutable {
      const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
      index.nearest(q, kk, idx, dist);
      keys.clear();
      for (std::size_t t = 0; t < idx.size(); ++t) keys.push_back(neighbor_key(dist[t], idx[t]));
      sorter.append(keys, keys.size(), out);
    };
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
