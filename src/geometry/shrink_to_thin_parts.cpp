#include "detexture/geometry/shrink_to_thin_parts.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "detexture/geometry/drop_opposite_neighbors.h"
#include "detexture/types.h"

namespace detexture {

void validate(const ShrinkToThinPartsParams& p) {
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("shrink_to_thin_parts: the radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.min_radius_fraction > 0.0 && p.min_radius_fraction <= 1.0))
    throw std::invalid_argument(
        "the least thin-part radius must be a fraction of r in (0, 1], got " +
        number_text(p.min_radius_fraction));
  if (!(p.back_angle_deg > 90.0 && p.back_angle_deg < 180.0))
    throw std::invalid_argument("the thin-part back angle must lie in (90, 180) degrees, got " +
                                number_text(p.back_angle_deg));
  if (!(p.plate_angle_deg >= 0.0 && p.plate_angle_deg < 90.0))
    throw std::invalid_argument("the plate angle must lie in [0, 90) degrees, got " +
                                number_text(p.plate_angle_deg));
}

ShrinkToThinPartsResult shrink_to_thin_parts(Neighborhoods& R, const Positions& P, const Normals& N,
                                             const ShrinkToThinPartsParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(N.rows()) != n || static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument(
        "shrink_to_thin_parts: positions, normals and neighborhoods differ in size");
  ShrinkToThinPartsResult out;
  if (params.min_radius_fraction >= 1.0) return out;
  const double back_cos = std::cos(params.back_angle_deg * M_PI / 180.0);
  const double plate_cos = std::cos(params.plate_angle_deg * M_PI / 180.0);
  const double least = params.min_radius_fraction * params.radius;
  std::vector<double> radius(n, params.radius);
  std::size_t cut = 0;
#pragma omp parallel for schedule(dynamic, 512) reduction(+ : cut)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::RowVector3d ni = N.row(i), pi = P.row(i);
    for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) {
      const Eigen::RowVector3d nj = N.row(*it), d = P.row(*it) - pi;
      // The first (nearest: rows are sorted by distance) back decides.
      if (is_back_of_part(ni, nj, d, back_cos)) {
        // Straight through either side's normal: the back of a plate.
        const double through = std::max(d.dot(nj), -d.dot(ni)) / d.norm();
        if (!(params.plate_angle_deg > 0.0 && through >= plate_cos)) {
          radius[i] = std::max(least, d.norm());
          cut += radius[i] < params.radius;
        }
        break;
      }
    }
  }
  out.points = cut;
  if (cut == 0) return out;
  out.removed = keep_neighbors(R, [&](std::size_t i, std::uint32_t j) {
    const double within = std::min(radius[i], radius[j]);
    return (P.row(j) - P.row(i)).squaredNorm() <= within * within;
  });
  return out;
}

}  // namespace detexture
