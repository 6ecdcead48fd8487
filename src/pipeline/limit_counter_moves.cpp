#include "detexture/pipeline/limit_counter_moves.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const LimitCounterMovesParams& p) {
  if (!(p.limit >= 0.0) || !std::isfinite(p.limit))
    throw std::invalid_argument(
        "the limit on moves against the relief (--counter-move-limit) must be >= 0, got " +
        number_text(p.limit));
  if (!(p.count_from >= 0.0) || !std::isfinite(p.count_from))
    throw std::invalid_argument(
        "the move from which the relief's lean counts a point must be >= 0, got " +
        number_text(p.count_from));
  if (!(p.min_lean > 0.0 && p.min_lean <= 1.0))
    throw std::invalid_argument(
        "the lean that decides the relief's side (--counter-move-lean) must be in (0, 1], got " +
        number_text(p.min_lean));
  if (!(p.height >= 0.0) || !std::isfinite(p.height))
    throw std::invalid_argument("limit_counter_moves: the texture height must be >= 0, got " +
                                number_text(p.height));
}

LimitCounterMovesResult limit_counter_moves(const Positions& P, const Positions& updated,
                                            const Normals& normals,
                                            const std::vector<std::uint8_t>& is_texture,
                                            const LimitCounterMovesParams& params) {
  validate(params);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (updated.rows() != P.rows() || normals.rows() != P.rows() || is_texture.size() != n)
    throw std::invalid_argument(
        "limit_counter_moves: positions, normals and labels differ in size");
  LimitCounterMovesResult out;
  out.positions = updated;
  if (params.limit == 0.0 || params.height == 0.0) return out;
  std::vector<double> t(n);
  std::size_t inward = 0, outward = 0;
  const double count_from = params.count_from * params.height;
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = (updated.row(i) - P.row(i)).dot(normals.row(i));
    if (!is_texture[i] || !std::isfinite(t[i])) continue;
    inward += t[i] < -count_from;
    outward += t[i] > count_from;
  }
  if (inward + outward == 0) return out;
  out.lean = (static_cast<double>(inward) - static_cast<double>(outward)) /
             static_cast<double>(inward + outward);
  if (out.lean >= params.min_lean)
    out.side = 1;
  else if (params.engraved && out.lean <= -params.min_lean)
    out.side = -1;
  if (out.side == 0) return out;
  const double limit = params.limit * params.height;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t[i])) continue;
    const double excess = out.side > 0 ? std::max(t[i] - limit, 0.0) : std::min(t[i] + limit, 0.0);
    if (excess == 0.0) continue;
    out.positions.row(i) -= excess * normals.row(i);
    ++out.limited;
  }
  return out;
}

}  // namespace detexture
