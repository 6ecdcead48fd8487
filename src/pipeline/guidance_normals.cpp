#include "detexture/pipeline/guidance_normals.h"

#include <algorithm>
#include <cmath>

#include "detexture/pipeline/estimate_curvature.h"

namespace detexture {

Normals guidance_normals(const Positions& P, const Normals& current, const Neighborhoods& R,
                         const GuidanceNormalsParams& params) {
  if (params.mode == GuidanceMode::Plain) return current;
  const std::size_t n = R.size();
  const Eigen::VectorXd C = estimate_curvature(P, current, R);

  // Eqs. 4-5: reliability of every point's patch.
  Eigen::VectorXd reliability(static_cast<Eigen::Index>(n));
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    double min_cos = 1.0;
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j)
      min_cos = std::min(min_cos, current.row(i).dot(current.row(*j)));
    min_cos = std::clamp(min_cos, -1.0, 1.0);
    const double D =
        params.difference == NormalDifference::Angle ? std::acos(min_cos) : 1.0 - min_cos;
    reliability(static_cast<Eigen::Index>(i)) = D * C(static_cast<Eigen::Index>(i));
  }

  // Eq. 8's σc: the mean of the neighborhood curvature sums.
  Eigen::VectorXd curvature_sum(static_cast<Eigen::Index>(n));
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    double s = 0.0;
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j) s += C(*j);
    curvature_sum(static_cast<Eigen::Index>(i)) = s;
  }
  const double sigma_c = n ? curvature_sum.sum() / static_cast<double>(n) : 0.0;

  Normals G(static_cast<Eigen::Index>(n), 3);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    // Eq. 6: the normal of the most reliable neighbor.
    std::uint32_t best = static_cast<std::uint32_t>(i);
    double best_r = reliability(static_cast<Eigen::Index>(i));
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j) {
      if (reliability(*j) < best_r) {
        best_r = reliability(*j);
        best = *j;
      }
    }
    Eigen::RowVector3d g = current.row(best);
    if (params.blend && sigma_c > 0.0) {
      // Eqs. 7-8.
      const double alpha = std::exp(-curvature_sum(static_cast<Eigen::Index>(i)) / sigma_c);
      g = alpha * g + (1.0 - alpha) * current.row(i);
    }
    const double norm = g.norm();
    G.row(i) = norm > 1e-12 ? Eigen::RowVector3d(g / norm) : Eigen::RowVector3d(current.row(i));
  }
  return G;
}

}  // namespace detexture
