#include "detexture/pipeline/limit_sink_moves.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "relief_along_normal.h"

namespace detexture {

void validate(const LimitSinkMovesParams& p) {
  if (!(p.depth >= 0.0) || !std::isfinite(p.depth))
    throw std::invalid_argument(
        "the relief height that makes a point's sink limited (--sink-depth) must be >= 0, got " +
        number_text(p.depth));
  if (!(p.slack >= 0.0) || !std::isfinite(p.slack))
    throw std::invalid_argument("the slack of the sink limit (--sink-slack) must be >= 0, got " +
                                number_text(p.slack));
  if (!(p.height >= 0.0) || !std::isfinite(p.height))
    throw std::invalid_argument("limit_sink_moves: the texture height must be >= 0, got " +
                                number_text(p.height));
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("limit_sink_moves: the radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.lambda > 0.0) || !std::isfinite(p.lambda))
    throw std::invalid_argument("limit_sink_moves: lambda must be positive, got " +
                                number_text(p.lambda));
}

LimitSinkMovesResult limit_sink_moves(const Positions& P, const Positions& updated,
                                      const Normals& normals,
                                      const std::vector<float>& surface_height,
                                      const Neighborhoods& R, bool raised,
                                      const LimitSinkMovesParams& params) {
  validate(params);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (updated.rows() != P.rows() || normals.rows() != P.rows() || surface_height.size() != n ||
      R.size() != n)
    throw std::invalid_argument(
        "limit_sink_moves: positions, normals, heights and neighborhoods differ in size");
  LimitSinkMovesResult out;
  out.positions = updated;
  if (params.slack == 0.0 || !raised) return out;
  const double radius_sq = params.radius * params.radius;
  const double depth = params.depth * params.lambda, slack = params.slack * params.lambda;
  std::size_t limited = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : limited)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::RowVector3d p = P.row(i), normal = normals.row(i);
    const double t = (updated.row(i) - p).dot(normal);
    const double deepest = -std::max(params.height, static_cast<double>(surface_height[i]) + slack);
    if (!(t < deepest)) continue;  // the common case: no neighbor loop
    if (relief_along_normal(P, R, i, normal, radius_sq).hi >= depth) {
      out.positions.row(i) += (deepest - t) * normal;
      ++limited;
    }
  }
  out.limited = limited;
  return out;
}

}  // namespace detexture
