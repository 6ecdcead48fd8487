#include "detexture/pipeline/limit_tip_moves.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "relief_along_normal.h"

namespace detexture {

void validate(const LimitTipMovesParams& p) {
  if (!(p.depth >= 0.0) || !std::isfinite(p.depth))
    throw std::invalid_argument(
        "the relief depth that makes a tip (--tip-depth) must be >= 0, got " +
        number_text(p.depth));
  if (!(p.slack >= 0.0) || !std::isfinite(p.slack))
    throw std::invalid_argument("the slack of the tip limit (--tip-slack) must be >= 0, got " +
                                number_text(p.slack));
  if (!(p.ceiling >= 0.0) || !std::isfinite(p.ceiling))
    throw std::invalid_argument("limit_tip_moves: the ceiling must be >= 0, got " +
                                number_text(p.ceiling));
  if (!(p.ceiling_min_cos >= -1.0 && p.ceiling_min_cos <= 1.0))
    throw std::invalid_argument("limit_tip_moves: ceiling_min_cos must be in [-1, 1], got " +
                                number_text(p.ceiling_min_cos));
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("limit_tip_moves: the radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.lambda > 0.0) || !std::isfinite(p.lambda))
    throw std::invalid_argument("limit_tip_moves: lambda must be positive, got " +
                                number_text(p.lambda));
}

LimitTipMovesResult limit_tip_moves(const Positions& P, const Positions& updated,
                                    const Normals& normals, const Neighborhoods& R,
                                    const LimitTipMovesParams& params) {
  validate(params);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (updated.rows() != P.rows() || normals.rows() != P.rows() || R.size() != n)
    throw std::invalid_argument(
        "limit_tip_moves: positions, normals and neighborhoods differ in size");
  LimitTipMovesResult out;
  out.positions = updated;
  if (params.depth == 0.0 && params.ceiling == 0.0) return out;
  const double radius_sq = params.radius * params.radius;
  const double depth = params.depth * params.lambda, slack = params.slack * params.lambda;
  const double ceiling = params.ceiling * params.lambda;
  std::size_t limited = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : limited)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::RowVector3d p = P.row(i), normal = normals.row(i);
    const double t = (updated.row(i) - p).dot(normal);
    double cut = t;
    if (params.depth > 0.0) {
      const auto [hi, lo] = relief_along_normal(P, R, i, normal, radius_sq);
      if (hi <= slack && lo <= -depth) cut = std::min(t, hi + slack);  // a peak
      if (lo >= -slack && hi >= depth) cut = std::max(t, lo - slack);  // a pit
    }
    if (ceiling > 0.0 && std::abs(cut) > ceiling) {
      const auto [hi, lo] =
          relief_along_normal(P, R, i, normal, radius_sq, &normals, params.ceiling_min_cos);
      if (-lo > hi) cut = std::min(cut, ceiling);   // the upper half
      if (hi > -lo) cut = std::max(cut, -ceiling);  // the lower half
    }
    if (cut != t && std::isfinite(t)) {
      out.positions.row(i) += (cut - t) * normal;
      ++limited;
    }
  }
  out.limited = limited;
  return out;
}

}  // namespace detexture
