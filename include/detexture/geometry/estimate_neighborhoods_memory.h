// How much memory the radius neighborhoods R_i (and the run around them) will
// take, estimated from a sample of the cloud before they are built, so that a
// radius covering much of a large cloud is refused in a second with a message
// instead of failing with std::bad_alloc after minutes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// Thrown when a run would exceed a resource limit (memory). The message says
/// what, how much, and what to change. The CLI exits with code 5 for it.
struct ResourceLimitError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct NeighborhoodsMemoryEstimate {
  std::size_t sampled = 0;        ///< points whose neighbors were counted
  double mean_neighbors = 0.0;    ///< estimated mean |R_i| (self included, after the cap)
  std::size_t max_neighbors = 0;  ///< largest |R_i| among the sampled points
  /// Estimated peak bytes of remove_texture: 4 bytes per neighbor index (plus
  /// 5% slack for the growing array) and kBytesPerPoint per point for
  /// everything else (measured: 966 bytes per point at 189 neighbors, of which
  /// 756 are the indices).
  double bytes = 0.0;
};

/// Bytes per point besides the neighbor indices, in the estimate above.
constexpr double kBytesPerPoint = 256.0;

/// Estimate the size of radius_neighborhoods(P, params) by counting, with the
/// point index, the neighbors of `samples` points spread evenly over P's rows
/// (all points when P has fewer). Deterministic. Costs up to `samples` radius
/// queries. Sampling stops early once the estimate is sure to exceed
/// `stop_above_bytes` whatever the remaining samples hold (each holds at
/// least itself); `sampled` then says how many were counted and `bytes` is a
/// lower bound. So a radius covering all of 3M points is refused after one
/// query (0.1 s) instead of 256 (36 s). Throws std::invalid_argument for a
/// non-positive radius.
NeighborhoodsMemoryEstimate estimate_neighborhoods_memory(
    const Positions& P, const RadiusNeighborhoodsParams& params, std::size_t samples = 256,
    double stop_above_bytes = std::numeric_limits<double>::infinity());

/// 80% of the machine's physical memory, in bytes (the default of
/// RemoveTextureParams::memory_limit); 0 if it cannot be found out.
std::uint64_t default_memory_limit();

/// Parse a size such as "4G", "500M", "64k", "1.5G" or "123456" (bytes;
/// K, M, G, T are powers of 1024, case-insensitive, optional trailing "B"),
/// or "none" (no limit: the largest uint64). Throws std::invalid_argument
/// with a sentence for anything else.
std::uint64_t parse_memory_size(const std::string& text);

/// "3.2 GiB", "512 MiB", ... for messages.
std::string memory_size_text(double bytes);

}  // namespace detexture
