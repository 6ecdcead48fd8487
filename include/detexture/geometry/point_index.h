// A spatial index over a cloud's positions, for searches from other points
// (nearest sample of a ground truth, feature centers near a sample). It is the
// one place where nanoflann is used: the k-d tree never leaks into a header.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "detexture/types.h"

namespace detexture {

class PointIndex {
 public:
  /// Index the rows of P (#P by 3). P is referenced, not copied: it must
  /// outlive the index and not change. Queries are const and thread-safe.
  explicit PointIndex(const Positions& P);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  /// Index of the row of P nearest to q; its squared distance in *distance_sq.
  /// P must not be empty.
  std::uint32_t nearest(const double q[3], double* distance_sq) const;

  /// k nearest rows of P to q, nearest first (ties by index); k is clamped to #P.
  void nearest(const double q[3], std::size_t k, std::vector<std::uint32_t>& index,
               std::vector<double>& distance_sq) const;

  /// Every row of P within `radius` of q (radius, not its square: it is
  /// squared here), as (index, squared distance) in a fixed but unspecified
  /// order.
  void within(const double q[3], double radius,
              std::vector<std::pair<std::uint32_t, double>>& found) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace detexture
