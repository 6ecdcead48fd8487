#include "detexture/pipeline/drop_neighbors_across_surfaces.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const DropNeighborsAcrossSurfacesParams& p) {
  if (!(p.max_angle_deg > 0.0 && p.max_angle_deg <= 180.0))
    throw std::invalid_argument("the surface split angle must lie in (0, 180] degrees, got " +
                                number_text(p.max_angle_deg));
}

std::size_t drop_neighbors_across_surfaces(Neighborhoods& R, const Normals& N,
                                           const Normals& surface_normals,
                                           const std::vector<std::uint8_t>& is_texture,
                                           const DropNeighborsAcrossSurfacesParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(N.rows()) != n ||
      static_cast<std::size_t>(surface_normals.rows()) != n || is_texture.size() != n)
    throw std::invalid_argument(
        "drop_neighbors_across_surfaces: normals, surface normals, labels and neighborhoods "
        "differ in size (" +
        std::to_string(N.rows()) + ", " + std::to_string(surface_normals.rows()) + ", " +
        std::to_string(is_texture.size()) + ", " + std::to_string(n) + ")");
  if (params.max_angle_deg >= 180.0) return 0;
  const double min_cos = std::cos(params.max_angle_deg * M_PI / 180.0);
  // Whether a accepts b: a's reference normal within the angle of b's normal.
  auto accepts = [&](std::size_t a, std::size_t b) {
    const auto ref = is_texture[a] ? surface_normals.row(static_cast<Eigen::Index>(a))
                                   : N.row(static_cast<Eigen::Index>(a));
    const auto nb = N.row(static_cast<Eigen::Index>(b));
    if (ref.squaredNorm() == 0.0 || nb.squaredNorm() == 0.0) return true;  // nothing to judge by
    return ref.dot(nb) >= min_cos;
  };
  return keep_neighbors(R, [&](std::size_t i, std::uint32_t j) {
    // A point always keeps itself, even on a flank steeper than the angle.
    return j == i || accepts(i, j) || accepts(j, i);
  });
}

}  // namespace detexture
