// A cache-friendly order of the points: along a Morton (Z-order) curve.
//
// Every stage walks each point's neighbors; when neighbors are also near each
// other in memory, those walks hit the cache. Scans usually come in scan-line
// order, which is close to this; clouds in random order (resampled,
// merged, synthetic) run several times slower without it.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/types.h"

namespace detexture {

/// The permutation that sorts P along a Morton curve over its bounding box:
/// order[k] is the index of the k-th point. Ties (points in the same cell of
/// the 2^21 grid) keep their input order, so the result is deterministic.
std::vector<std::uint32_t> spatial_order(const Positions& P);

/// Rows of M in the given order: result.row(k) = M.row(order[k]).
Matrix3 permute_rows(const Matrix3& M, const std::vector<std::uint32_t>& order);

/// The inverse: result.row(order[k]) = M.row(k).
Matrix3 unpermute_rows(const Matrix3& M, const std::vector<std::uint32_t>& order);

}  // namespace detexture
