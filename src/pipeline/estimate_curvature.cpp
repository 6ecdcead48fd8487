#include "detexture/pipeline/estimate_curvature.h"

#include <algorithm>
#include <cmath>

namespace detexture {

Eigen::VectorXd estimate_curvature(const Positions& P, const Normals& normals,
                                   const Neighborhoods& R, Eigen::VectorXd* min_cos) {
  const std::size_t n = R.size();
  Eigen::VectorXd C(static_cast<Eigen::Index>(n));
  if (min_cos) min_cos->resize(static_cast<Eigen::Index>(n));
  const double* p = P.data();
  const double* nc = normals.data();
  // Raw row-major access: this runs once per rolling iteration over every pair.
#pragma omp parallel for schedule(dynamic, 512)
  for (std::size_t i = 0; i < n; ++i) {
    const double px = p[3 * i], py = p[3 * i + 1], pz = p[3 * i + 2];
    const double nx = nc[3 * i], ny = nc[3 * i + 1], nz = nc[3 * i + 2];
    double sum = 0.0, lowest = 1.0;
    int count = 0;
    for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) {
      const std::size_t j = *it;
      const double dx = px - p[3 * j], dy = py - p[3 * j + 1], dz = pz - p[3 * j + 2];
      const double len_sq = dx * dx + dy * dy + dz * dz;
      if (len_sq <= 0.0) continue;
      const double* nj = nc + 3 * j;
      lowest = std::min(lowest, nx * nj[0] + ny * nj[1] + nz * nj[2]);
      sum += ((nx - nj[0]) * dx + (ny - nj[1]) * dy + (nz - nj[2]) * dz) / len_sq;
      ++count;
    }
    C(static_cast<Eigen::Index>(i)) = count ? std::abs(sum / count) : 0.0;
    if (min_cos) (*min_cos)(static_cast<Eigen::Index>(i)) = lowest;
  }
  return C;
}

}  // namespace detexture
