#include "detexture/geometry/orient_normals.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace detexture {
namespace {

constexpr double kPi = 3.14159265358979323846;

void check_graph(const Neighborhoods& N, std::size_t n, const char* what) {
  if (N.size() != n)
    throw std::invalid_argument("the neighborhoods were computed for " + std::to_string(N.size()) +
                                " points, but there are " + std::to_string(n) + " " + what);
  if (!N.offsets.empty() && N.offsets.back() != N.indices.size())
    throw std::invalid_argument(
        "the neighborhoods are malformed: the last offset is not the number of indices");
  std::uint32_t largest = 0;
  const std::ptrdiff_t m = static_cast<std::ptrdiff_t>(N.indices.size());
#pragma omp parallel for schedule(static) reduction(max : largest)
  for (std::ptrdiff_t e = 0; e < m; ++e) largest = std::max(largest, N.indices[e]);
  if (m > 0 && largest >= n)
    throw std::invalid_argument("the neighborhoods refer to point " + std::to_string(largest) +
                                ", but there are only " + std::to_string(n) + " " + what);
}

bool contains(const Neighborhoods& N, std::size_t row, std::uint32_t value) {
  return std::find(N.begin(row), N.end(row), value) != N.end(row);
}

// The edges that make N undirected: j -> i for every i -> j of N whose
// reverse is missing (i not in N_j). Empty rows for a symmetric (radius)
// graph. Rows are sorted by index, so the result is the same for any number
// of threads.
Neighborhoods missing_reverse_edges(const Neighborhoods& N) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(N.size());
  std::vector<std::uint8_t> missing(N.indices.size(), 0);  // per edge i -> j of N
  std::vector<std::atomic<std::uint32_t>> count(n);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    for (std::uint64_t e = N.offsets[i]; e < N.offsets[i + 1]; ++e) {
      const std::uint32_t j = N.indices[e];
      if (j == i || contains(N, j, static_cast<std::uint32_t>(i))) continue;
      missing[e] = 1;
      count[j].fetch_add(1, std::memory_order_relaxed);
    }
  Neighborhoods reverse;
  reverse.offsets.assign(n + 1, 0);
  for (std::ptrdiff_t i = 0; i < n; ++i) reverse.offsets[i + 1] = reverse.offsets[i] + count[i];
  reverse.indices.resize(reverse.offsets[n]);
  if (reverse.indices.empty()) return reverse;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    for (std::uint64_t e = N.offsets[i]; e < N.offsets[i + 1]; ++e) {
      if (!missing[e]) continue;
      const std::uint32_t j = N.indices[e];
      const std::uint32_t slot = count[j].fetch_sub(1, std::memory_order_relaxed) - 1;
      reverse.indices[reverse.offsets[j] + slot] = static_cast<std::uint32_t>(i);
    }
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t i = 0; i < n; ++i)
    std::sort(reverse.indices.begin() + reverse.offsets[i],
              reverse.indices.begin() + reverse.offsets[i + 1]);
  return reverse;
}

// What Prim's algorithm knows about one point.
struct alignas(64) Node {
  Eigen::Vector3d position;
  Eigen::Vector3d normal;                              // unit, or zero
  float key = std::numeric_limits<float>::infinity();  // cost of the best edge found into it
  std::int32_t sign = 0;    // +-1: keep or flip the input normal; 0: zero normal
  std::int32_t closed = 0;  // visited, or a zero normal
};

inline void prefetch(const void* address) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(address);
#else
  (void)address;
#endif
}

// 4-ary min-heap of points keyed by a non-negative float, with decrease-key.
// An entry packs the key's bits (which order like the keys) above the point
// index, so one integer comparison orders by key, then by index: the order is
// fully determined, and sifting touches only the heap's own memory.
class PointHeap {
 public:
  explicit PointHeap(std::size_t n) : slot_(n, kAbsent) {}

  bool empty() const { return heap_.empty(); }

  // Insert v with this key, or lower the key of v if it is already queued.
  void push_or_decrease(std::uint32_t v, float key) {
    std::size_t s = slot_[v];
    if (s == kAbsent) {
      s = heap_.size();
      heap_.push_back(0);
    }
    sift_up(s, entry(v, key));
  }

  std::uint32_t top_point() const { return static_cast<std::uint32_t>(heap_.front()); }
  float top_key() const {
    const std::uint32_t bits = static_cast<std::uint32_t>(heap_.front() >> 32);
    float key;
    std::memcpy(&key, &bits, sizeof key);
    return key;
  }

  void pop() {
    slot_[top_point()] = kAbsent;
    const std::uint64_t last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0, last);
  }

 private:
  static constexpr std::uint32_t kAbsent = std::numeric_limits<std::uint32_t>::max();
  static constexpr std::size_t kArity = 4;

  static std::uint64_t entry(std::uint32_t v, float key) {
    std::uint32_t bits;
    std::memcpy(&bits, &key, sizeof bits);
    return static_cast<std::uint64_t>(bits) << 32 | v;
  }
  void place(std::size_t s, std::uint64_t e) {
    heap_[s] = e;
    slot_[static_cast<std::uint32_t>(e)] = static_cast<std::uint32_t>(s);
  }
  // Put e into the hole at s and move it up to its place.
  void sift_up(std::size_t s, std::uint64_t e) {
    while (s > 0) {
      const std::size_t up = (s - 1) / kArity;
      if (heap_[up] <= e) break;
      place(s, heap_[up]);
      s = up;
    }
    place(s, e);
  }
  // Put e into the hole at s and move it down to its place.
  void sift_down(std::size_t s, std::uint64_t e) {
    const std::size_t size = heap_.size();
    while (true) {
      const std::size_t first = kArity * s + 1;
      if (first >= size) break;
      const std::size_t last = std::min(first + kArity, size);
      std::size_t child = first;
      for (std::size_t c = first + 1; c < last; ++c)
        if (heap_[c] < heap_[child]) child = c;
      if (heap_[child] >= e) break;
      place(s, heap_[child]);
      s = child;
    }
    place(s, e);
  }

  std::vector<std::uint32_t> slot_;
  std::vector<std::uint64_t> heap_;
};

// What one edge u-v says: its Prim key, and n_u⊥·n_v⊥ whose sign tells
// whether n_v agrees with n_u (see the header for both).
struct EdgeMeasure {
  double key;
  double projected;
};

class EdgeMeasurer {
 public:
  explicit EdgeMeasurer(double cross_sheet_angle)
      : cos_excess_(std::cos(cross_sheet_angle * kPi / 180.0)),
        sin_excess_(std::sin(cross_sheet_angle * kPi / 180.0)) {}

  // nu and nv are unit normals (their signs do not change the key).
  EdgeMeasure operator()(const Eigen::Vector3d& pu, const Eigen::Vector3d& nu,
                         const Eigen::Vector3d& pv, const Eigen::Vector3d& nv) const {
    const double c = nu.dot(nv);
    const Eigen::Vector3d d = pv - pu;
    const double length_sq = d.squaredNorm();
    if (length_sq == 0.0) return {1.0 - std::abs(c), c};
    const double inverse_length = 1.0 / std::sqrt(length_sq);
    const double a = d.dot(nu) * inverse_length;  // sin of the elevation above u's tangent plane
    const double b = d.dot(nv) * inverse_length;
    const double projected = c - a * b;
    const double cost = std::max(0.0, 1.0 - std::abs(projected));
    // Cross-sheet test α_u + α_v > θ + E, done on cosines to avoid trigonometry
    // in the inner loop: both sides lie in [0, π], where cos is decreasing.
    const double sa = std::min(std::abs(a), 1.0), sb = std::min(std::abs(b), 1.0);
    const double cos_theta = std::min(std::abs(c), 1.0);
    const double cos_elevations = std::sqrt((1.0 - sa * sa) * (1.0 - sb * sb)) - sa * sb;
    const double cos_limit =
        cos_theta * cos_excess_ - std::sqrt(1.0 - cos_theta * cos_theta) * sin_excess_;
    const bool cross_sheet = cos_elevations < cos_limit;
    return {cross_sheet ? cost + 2.0 : cost, projected};
  }

 private:
  double cos_excess_, sin_excess_;
};

// Whether a component whose relative signs are final must be turned over to
// face `side` (the header's "Side"): for Auto, outward by the flux
// Σ n̂·(p - c) when it is clear, up for a flat open sheet; for the others,
// their rule. What the rule leaves undecided goes outward at the point
// farthest from the centroid c.
bool flip_component(const std::vector<std::uint32_t>& members, const std::vector<Node>& node,
                    NormalSide side) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const std::uint32_t v : members) centroid += node[v].position;
  centroid /= static_cast<double>(members.size());
  double flux = 0.0, distances = 0.0;
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero();
  for (const std::uint32_t v : members) {
    const Eigen::Vector3d offset = node[v].position - centroid;
    const Eigen::Vector3d oriented = node[v].sign * node[v].normal;
    flux += oriented.dot(offset);
    distances += offset.norm();
    resultant += oriented;
  }
  switch (side) {
    case NormalSide::Auto: {
      if (std::abs(flux) >= kOutwardFluxRatio * distances) return flux < 0.0;
      const double length = resultant.norm();
      if (length >= kOpenSheetResultant * static_cast<double>(members.size()) &&
          std::abs(resultant.z()) >= kUpwardCosine * length)
        return resultant.z() < 0.0;
      break;
    }
    case NormalSide::Outward:
    case NormalSide::Inward:
      if (flux != 0.0) return (flux < 0.0) == (side == NormalSide::Outward);
      break;
    default: {  // PlusX, MinusX, PlusY, ...: axis k, sign by the parity of the offset
      const int k = (static_cast<int>(side) - static_cast<int>(NormalSide::PlusX)) / 2;
      const bool plus = (static_cast<int>(side) - static_cast<int>(NormalSide::PlusX)) % 2 == 0;
      if (resultant(k) != 0.0) return (resultant(k) < 0.0) == plus;
      break;
    }
  }
  std::uint32_t farthest = members.front();
  double farthest_sq = -1.0;
  for (const std::uint32_t v : members) {
    const double distance_sq = (node[v].position - centroid).squaredNorm();
    if (distance_sq > farthest_sq || (distance_sq == farthest_sq && v < farthest)) {
      farthest = v;
      farthest_sq = distance_sq;
    }
  }
  const Node& f = node[farthest];
  return f.sign * f.normal.dot(f.position - centroid) < 0.0;
}

}  // namespace

OrientNormalsResult orient_normals(const Positions& P, const Normals& normals,
                                   const Neighborhoods& N) {
  return orient_normals(P, normals, N, OrientNormalsParams{});
}

void validate(const OrientNormalsParams& params) {
  if (!(params.cross_sheet_angle > 0.0 && params.cross_sheet_angle <= 90.0))
    throw std::invalid_argument("the cross-sheet angle must be in (0, 90] degrees, got " +
                                std::to_string(params.cross_sheet_angle));
  if (static_cast<int>(params.side) < static_cast<int>(NormalSide::Auto) ||
      static_cast<int>(params.side) > static_cast<int>(NormalSide::MinusZ))
    throw std::invalid_argument("the normal side is not one of NormalSide's values");
}

OrientNormalsResult orient_normals(const Positions& P, const Normals& normals,
                                   const Neighborhoods& N, const OrientNormalsParams& params) {
  validate(params);
  if (normals.rows() != P.rows())
    throw std::invalid_argument("the cloud has " + std::to_string(P.rows()) + " points but " +
                                std::to_string(normals.rows()) + " normals");
  const std::size_t n = static_cast<std::size_t>(P.rows());
  check_graph(N, n, "points");
  if (n >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("clouds of more than 2^32-1 points are not supported");

  // Everything Prim's algorithm reads about a neighbor, in one cache line.
  std::vector<Node> node(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
    const double length = normals.row(i).norm();
    node[i].position = P.row(i).transpose();
    node[i].normal =
        length > 0.0 ? (normals.row(i).transpose() / length).eval() : Eigen::Vector3d::Zero();
    node[i].sign = length > 0.0 ? 1 : 0;
    node[i].closed = length > 0.0 ? 0 : 1;  // zero normals are never visited
  }
  const Neighborhoods reverse = missing_reverse_edges(N);
  const EdgeMeasurer measure(params.cross_sheet_angle);

  OrientNormalsResult result;
  PointHeap heap(n);
  std::vector<std::uint32_t> members;

  // Prim's algorithm, one component at a time. node[v].sign holds the sign
  // that the best edge into v so far would give it; final when v is popped.
  auto relax = [&](const Node& u, const Eigen::Vector3d& nu, const std::uint32_t* begin,
                   const std::uint32_t* end) {
    for (const std::uint32_t* it = begin; it != end; ++it) {
      Node& v = node[*it];
      if (v.closed) continue;
      const EdgeMeasure e = measure(u.position, nu, v.position, v.normal);
      const float key = static_cast<float>(e.key);
      if (key < v.key) {
        v.key = key;
        v.sign = e.projected < 0.0 ? -1 : 1;
        heap.push_or_decrease(*it, key);
      }
    }
  };
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (node[seed].closed) continue;
    members.clear();
    heap.push_or_decrease(static_cast<std::uint32_t>(seed), 0.0f);
    while (!heap.empty()) {
      const std::uint32_t top = heap.top_point();
      if (heap.top_key() >= 2.0f) ++result.cross_sheet_edges;
      heap.pop();
      Node& u = node[top];
      u.closed = 1;
      members.push_back(top);
      // Start loading all neighbors at once rather than one cache miss at a time.
      for (const std::uint32_t* it = N.begin(top); it != N.end(top); ++it) prefetch(&node[*it]);
      for (const std::uint32_t* it = reverse.begin(top); it != reverse.end(top); ++it)
        prefetch(&node[*it]);
      const Eigen::Vector3d nu = u.sign * u.normal;
      relax(u, nu, N.begin(top), N.end(top));
      relax(u, nu, reverse.begin(top), reverse.end(top));
    }

    if (flip_component(members, node, params.side)) {
      for (const std::uint32_t v : members) node[v].sign = -node[v].sign;
    }
    ++result.components;
  }

  result.normals.resize(n, 3);
  std::size_t flipped = 0;
#pragma omp parallel for schedule(static) reduction(+ : flipped)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
    const bool flip = node[i].sign < 0;
    result.normals.row(i) = flip ? (-normals.row(i)).eval() : normals.row(i);
    if (flip) ++flipped;
  }
  result.flipped = flipped;
  return result;
}

double orientation_inconsistency(const Normals& normals, const Neighborhoods& N,
                                 std::size_t nearest) {
  const std::ptrdiff_t n = normals.rows();
  check_graph(N, static_cast<std::size_t>(n), "normals");
  std::vector<double> inverse_length(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const double length = normals.row(i).norm();
    inverse_length[i] = length > 0.0 ? 1.0 / length : 0.0;
  }
  std::size_t comparable = 0, opposite = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : comparable, opposite)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (inverse_length[i] == 0.0) continue;
    const std::uint32_t* end =
        nearest > 0 && N.count(i) > nearest ? N.begin(i) + nearest : N.end(i);
    for (const std::uint32_t* j = N.begin(i); j != end; ++j) {
      if (*j == i || inverse_length[*j] == 0.0) continue;
      const double c = normals.row(i).dot(normals.row(*j)) * inverse_length[i] * inverse_length[*j];
      if (std::abs(c) < kComparableNormalsCosine) continue;
      ++comparable;
      if (c < 0.0) ++opposite;
    }
  }
  return comparable == 0 ? 0.0 : static_cast<double>(opposite) / static_cast<double>(comparable);
}

}  // namespace detexture
