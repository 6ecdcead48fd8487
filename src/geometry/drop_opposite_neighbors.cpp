#include "detexture/geometry/drop_opposite_neighbors.h"

#include <cmath>
#include <stdexcept>

namespace detexture {

void validate(const DropOppositeNeighborsParams& p) {
  if (!(p.max_angle_deg > 0.0 && p.max_angle_deg <= 180.0))
    throw std::invalid_argument("the sheet angle must lie in (0, 180] degrees, got " +
                                number_text(p.max_angle_deg));
}

std::size_t drop_opposite_neighbors(Neighborhoods& R, const Positions& P, const Normals& N,
                                    const DropOppositeNeighborsParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(N.rows()) != n || static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument(
        "drop_opposite_neighbors: positions, normals and neighborhoods differ in size");
  if (params.max_angle_deg >= 180.0) return 0;
  const double min_cos = std::cos(params.max_angle_deg * M_PI / 180.0);
  return keep_neighbors(R, [&](std::size_t i, std::uint32_t j) {
    const double nx = N(i, 0), ny = N(i, 1), nz = N(i, 2);
    const double c = nx * N(j, 0) + ny * N(j, 1) + nz * N(j, 2);
    // A zero normal gives c = 0, kept for any angle of at least 90°; below
    // that, only a pair with a known normal can be judged.
    const bool judged = (nx != 0.0 || ny != 0.0 || nz != 0.0) &&
                        (N(j, 0) != 0.0 || N(j, 1) != 0.0 || N(j, 2) != 0.0);
    if (!judged || c >= min_cos) return true;
    if (!params.back_to_back_only) return false;
    return !is_back_of_part(N.row(i), N.row(j), P.row(j) - P.row(i), min_cos);
  });
}

}  // namespace detexture
