#include "detexture/geometry/estimate_neighborhoods_memory.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "detexture/geometry/point_index.h"

namespace detexture {

namespace {
double bytes_for(std::size_t points, double mean_neighbors) {
  return static_cast<double>(points) * (4.0 * 1.05 * mean_neighbors + kBytesPerPoint);
}
}  // namespace

NeighborhoodsMemoryEstimate estimate_neighborhoods_memory(const Positions& P,
                                                          const RadiusNeighborhoodsParams& params,
                                                          std::size_t samples,
                                                          double stop_above_bytes) {
  if (!(params.radius > 0.0) || !std::isfinite(params.radius))
    throw std::invalid_argument("the neighborhood radius must be a positive number, got " +
                                number_text(params.radius));
  NeighborhoodsMemoryEstimate e;
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (n == 0) return e;
  const std::size_t m = std::max<std::size_t>(1, std::min(samples, n));
  const std::size_t cap = params.max_neighbors > 0 ? static_cast<std::size_t>(params.max_neighbors)
                                                   : std::numeric_limits<std::size_t>::max();
  const PointIndex index(P);
  std::vector<std::pair<std::uint32_t, double>> found;
  double total = 0.0;
  for (std::size_t s = 0; s < m; ++s) {
    // The middle of each of m equal runs of rows: spread over a spatially
    // ordered cloud, and over any other order too.
    const std::size_t i = (2 * s + 1) * n / (2 * m);
    const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
    index.within(q, params.radius, found);
    const std::size_t count = std::min(found.size(), cap);
    total += static_cast<double>(count);
    e.max_neighbors = std::max(e.max_neighbors, count);
    e.sampled = s + 1;
    const double lower_mean = (total + static_cast<double>(m - s - 1)) / static_cast<double>(m);
    if (bytes_for(n, lower_mean) > stop_above_bytes) {
      e.mean_neighbors = total / static_cast<double>(e.sampled);
      e.bytes = bytes_for(n, lower_mean);
      return e;
    }
  }
  e.mean_neighbors = total / static_cast<double>(m);
  e.bytes = bytes_for(n, e.mean_neighbors);
  return e;
}

std::uint64_t default_memory_limit() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::uint64_t>(0.8 * static_cast<double>(pages) * static_cast<double>(page));
}

std::uint64_t parse_memory_size(const std::string& text) {
  std::string t;
  for (const char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "none") return std::numeric_limits<std::uint64_t>::max();
  const auto fail = [&]() -> std::uint64_t {
    throw std::invalid_argument("'" + text +
                                "' is not a memory size: give bytes, or a number with K, M, G "
                                "or T (powers of 1024) such as 500M or 4G, or 'none'");
  };
  if (!t.empty() && t.back() == 'b') t.pop_back();
  double unit = 1.0;
  if (!t.empty()) {
    const char u = t.back();
    const double units[] = {1024.0, 1024.0 * 1024, 1024.0 * 1024 * 1024,
                            1024.0 * 1024 * 1024 * 1024};
    const char* names = "kmgt";
    if (const char* p = std::strchr(names, u); p && u != '\0') {
      unit = units[p - names];
      t.pop_back();
    }
  }
  if (t.empty()) return fail();
  char* end = nullptr;
  const double value = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || !std::isfinite(value) || !(value > 0.0)) return fail();
  const double bytes = value * unit;
  if (bytes >= 1.8e19) return fail();
  return static_cast<std::uint64_t>(bytes);
}

std::string memory_size_text(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 6) {
    bytes /= 1024.0;
    ++u;
  }
  char text[64];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return text;
}

}  // namespace detexture
