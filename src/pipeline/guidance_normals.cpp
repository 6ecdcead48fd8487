#include "detexture/pipeline/guidance_normals.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "detexture/pipeline/estimate_curvature.h"

namespace detexture {

Normals guidance_normals(const Positions& P, const Normals& current, const Neighborhoods& R,
                         const GuidanceNormalsParams& params) {
  if (params.mode == GuidanceMode::Plain) return current;
  const std::size_t n = R.size();
  const bool angle = params.difference == NormalDifference::Angle;

  // Eqs. 4-5: reliability R(p_i) = max_j D(p_ij)·C(p_i); D grows as n_i·n_j
  // falls. It is written over min_cos, and the per-point arrays are freed as
  // soon as they are used: this runs inside the rolling filter, at the
  // method's peak memory.
  std::vector<std::uint32_t> best(n);
  std::vector<double> curvature_sum(n);
  {
    Eigen::VectorXd reliability;  // min cos first
    const Eigen::VectorXd C = estimate_curvature(P, current, R, &reliability);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Index e = static_cast<Eigen::Index>(i);
      const double c = std::clamp(reliability(e), -1.0, 1.0);
      reliability(e) = (angle ? std::acos(c) : 1.0 - c) * C(e);
    }

    // Pass 2, Eq. 6: the most reliable neighbor; and Eq. 8's sums Σ_j C(p_j).
#pragma omp parallel for schedule(dynamic, 512)
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t b = static_cast<std::uint32_t>(i);
      double best_r = reliability(static_cast<Eigen::Index>(i)), s = 0.0;
      for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) {
        s += C(*it);
        if (reliability(*it) < best_r) {  // ties go to the nearer neighbor
          best_r = reliability(*it);
          b = *it;
        }
      }
      best[i] = b;
      curvature_sum[i] = s;
    }
  }
  double total = 0.0;
  for (double s : curvature_sum) total += s;
  const double sigma_c = n ? total / static_cast<double>(n) : 0.0;

  // Eq. 7: blend toward the current normal where the surroundings are curved.
  Normals G(static_cast<Eigen::Index>(n), 3);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::RowVector3d g = current.row(best[i]);
    if (params.blend && sigma_c > 0.0) {
      const double alpha = std::exp(-curvature_sum[i] / sigma_c);  // Eq. 8
      g = alpha * g + (1.0 - alpha) * current.row(i);
    }
    const double norm = g.norm();
    G.row(i) = norm > 1e-12 ? Eigen::RowVector3d(g / norm) : Eigen::RowVector3d(current.row(i));
  }
  return G;
}

}  // namespace detexture
