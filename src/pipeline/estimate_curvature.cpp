#include "detexture/pipeline/estimate_curvature.h"

#include <cmath>

namespace detexture {

Eigen::VectorXd estimate_curvature(const Positions& P, const Normals& normals,
                                   const Neighborhoods& R) {
  const std::size_t n = R.size();
  Eigen::VectorXd C(static_cast<Eigen::Index>(n));
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    double sum = 0.0;
    int count = 0;
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j) {
      if (*j == i) continue;
      const Eigen::RowVector3d d = P.row(i) - P.row(*j);
      const double len_sq = d.squaredNorm();
      if (len_sq <= 0.0) continue;
      sum += (normals.row(i) - normals.row(*j)).dot(d) / len_sq;
      ++count;
    }
    C(static_cast<Eigen::Index>(i)) = count ? std::abs(sum / count) : 0.0;
  }
  return C;
}

}  // namespace detexture
