// Internal to the stages after the update (limit_tip_moves, limit_sink_moves):
// how far the input relief around a point rises above it and falls below
// it along a normal, within a radius.
//
//   h_ij = (p_j - p_i)·n          j ∈ R_i, |p_j - p_i| <= ρ
//   hi = max(0, max_j h_ij),  lo = min(0, min_j h_ij)
//
// Given normals, only the neighbors whose normals agree with n count
// (limit_tip_moves' ceiling).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct ReliefAlongNormal {
  double hi = 0.0;  ///< >= 0
  double lo = 0.0;  ///< <= 0
};

/// P  #P by 3 input positions; i  the point; normal  the direction n;
/// radius_sq  ρ², the squared radius; agreeing  #P by 3 unit normals N, or
/// null: when given, only the neighbors j with N_j·n >= min_cos count.
inline ReliefAlongNormal relief_along_normal(const Positions& P, const Neighborhoods& R,
                                             std::size_t i, const Eigen::RowVector3d& normal,
                                             double radius_sq, const Normals* agreeing = nullptr,
                                             double min_cos = -1.0) {
  ReliefAlongNormal r;
  const Eigen::RowVector3d p = P.row(static_cast<Eigen::Index>(i));
  for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) {
    const Eigen::RowVector3d d = P.row(*it) - p;
    if (d.squaredNorm() > radius_sq) continue;
    if (agreeing && agreeing->row(*it).dot(normal) < min_cos) continue;
    const double h = d.dot(normal);
    r.hi = std::max(r.hi, h);
    r.lo = std::min(r.lo, h);
  }
  return r;
}

}  // namespace detexture
