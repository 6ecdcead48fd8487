// Radius neighborhoods R_i (the paper's "RNN"), computed once for the whole
// cloud and stored flat, then passed to every stage.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/types.h"

namespace detexture {

/// Compressed rows: the neighbors of point i are
/// indices[offsets[i] .. offsets[i+1]), sorted by increasing distance (the
/// squared distance rounded to float), ties by index: the point itself comes
/// first unless it has exact duplicates. Squared distances are not stored
/// (they are cheap to recompute and would double the memory).
struct Neighborhoods {
  std::vector<std::uint64_t> offsets;  ///< #P+1
  std::vector<std::uint32_t> indices;  ///< offsets.back()
  /// True when j ∈ R_i exactly if i ∈ R_j (radius search with no row cut by
  /// a cap): stages may then gather over R_j what R_i would scatter to j.
  bool symmetric = false;

  std::size_t size() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t count(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  const std::uint32_t* begin(std::size_t i) const { return indices.data() + offsets[i]; }
  const std::uint32_t* end(std::size_t i) const { return indices.data() + offsets[i + 1]; }
};

struct RadiusNeighborhoodsParams {
  double radius = 0.0;    ///< r: search radius, in the cloud's units; > 0
  int max_neighbors = 0;  ///< keep at most this many nearest (self included); 0 = no cap
};

struct NeighborhoodStats {
  std::size_t min = 0, max = 0;
  double mean = 0.0;
  std::size_t sparse_points = 0;  ///< points with fewer than min_count neighbors (self included)
};

/// All radius neighborhoods of P, built in parallel on a k-d tree (nanoflann).
/// Throws std::invalid_argument for a non-positive radius, or more than 2^32
/// points.
Neighborhoods radius_neighborhoods(const Positions& P, const RadiusNeighborhoodsParams& params,
                                   const ProgressFn& progress = {});

/// Cuts every row of R to its members within `radius` of the row's point (a
/// prefix: rows are sorted by distance), in place, and gives the memory freed
/// back to the system. Used before the position update, whose solve only
/// needs the inner part of R_i: the index array is most of the memory.
/// Throws std::invalid_argument for a negative radius or a size mismatch.
void shrink_neighborhoods(Neighborhoods& R, const Positions& P, double radius);

/// Keeps in every row of R, in place and in order, the neighbors j for which
/// keep(i, j) is true, and returns how many entries were removed. The stages
/// that take neighbors out of R_i (drop_opposite_neighbors,
/// shrink_to_thin_parts) share it; a symmetric keep keeps R symmetric.
template <class Keep>
std::size_t keep_neighbors(Neighborhoods& R, Keep&& keep) {
  const std::size_t n = R.size();
  std::uint64_t write = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t begin = R.offsets[i], end = R.offsets[i + 1];
    R.offsets[i] = write;
    for (std::uint64_t e = begin; e < end; ++e)
      if (keep(i, R.indices[e])) R.indices[write++] = R.indices[e];
  }
  const std::size_t removed = R.indices.size() - write;
  if (n > 0) R.offsets[n] = write;
  R.indices.resize(write);
  return removed;
}

/// The k nearest neighbors of every point (self included), same layout.
/// Used for orientation and for clouds too sparse for the chosen radius.
Neighborhoods knn_neighborhoods(const Positions& P, int k, const ProgressFn& progress = {});

/// Count statistics; points with fewer than min_count neighbors are "sparse".
NeighborhoodStats neighborhood_stats(const Neighborhoods& N, std::size_t min_count);

}  // namespace detexture
