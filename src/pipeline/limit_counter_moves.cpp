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
        "the lean that makes the relief raised (--counter-move-lean) must be in (0, 1], got " +
        number_text(p.min_lean));
  if (!(p.released_min_lean > 0.0 && p.released_min_lean <= 1.0))
    throw std::invalid_argument(
        "the lean that makes the relief raised in the waves pass (--counter-move-released-lean) "
        "must be in (0, 1], got " +
        number_text(p.released_min_lean));
  if (!(p.engraved_min_lean > 0.0 && p.engraved_min_lean <= 1.0))
    throw std::invalid_argument(
        "the lean that makes the relief engraved (--counter-move-engraved-lean) must be in (0, "
        "1], got " +
        number_text(p.engraved_min_lean));
  if (!(p.engraved_share >= 0.0 && p.engraved_share <= 1.0))
    throw std::invalid_argument(
        "the texture share under which engraved relief is limited "
        "(--counter-move-engraved-share) must be in [0, 1], got " +
        number_text(p.engraved_share));
  if (!(p.height >= 0.0) || !std::isfinite(p.height))
    throw std::invalid_argument("limit_counter_moves: the texture height must be >= 0, got " +
                                number_text(p.height));
}

LimitCounterMovesResult limit_counter_moves(const Positions& P, const Positions& updated,
                                            const Normals& normals,
                                            const std::vector<std::uint8_t>& is_texture,
                                            const LimitCounterMovesParams& params,
                                            const std::vector<std::uint8_t>& released) {
  validate(params);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (updated.rows() != P.rows() || normals.rows() != P.rows() || is_texture.size() != n)
    throw std::invalid_argument(
        "limit_counter_moves: positions, normals and labels differ in size");
  if (!released.empty() && released.size() != n)
    throw std::invalid_argument(
        "limit_counter_moves: the released flags differ in size from the positions");
  LimitCounterMovesResult out;
  out.positions = updated;
  // The lean is read with the limit off too: lower_raised_cells reads it.
  if (params.height == 0.0) return out;
  std::vector<double> t(n);
  std::size_t inward = 0, outward = 0, texture = 0;
  const double count_from = params.count_from * params.height;
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = (updated.row(i) - P.row(i)).dot(normals.row(i));
    if (!is_texture[i]) continue;
    ++texture;
    if (!std::isfinite(t[i])) continue;
    inward += t[i] < -count_from;
    outward += t[i] > count_from;
  }
  if (inward + outward == 0) return out;
  out.lean = (static_cast<double>(inward) - static_cast<double>(outward)) /
             static_cast<double>(inward + outward);
  if (out.lean >= (released.empty() ? params.min_lean : params.released_min_lean))
    out.side = 1;
  else if (out.lean <= -params.engraved_min_lean &&
           static_cast<double>(texture) <= params.engraved_share * static_cast<double>(n))
    out.side = -1;
  if (params.limit == 0.0) out.side = 0;
  if (out.side == 0) return out;
  const double limit = params.limit * params.height;
  const bool free_released = out.side > 0 && params.free_released && !released.empty();
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t[i])) continue;
    if (free_released && released[i]) continue;
    const double against = out.side > 0 ? t[i] : -t[i];
    if (against <= 0.0) continue;
    const double kept = params.soft ? limit * std::tanh(against / limit) : std::min(against, limit);
    out.positions.row(i) -= static_cast<double>(out.side) * (against - kept) * normals.row(i);
    out.limited += against > (params.soft ? 0.5 : 1.0) * limit;
  }
  return out;
}

}  // namespace detexture
