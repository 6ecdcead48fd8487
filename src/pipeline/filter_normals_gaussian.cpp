#include "detexture/pipeline/filter_normals_gaussian.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const FilterNormalsGaussianParams& p) {
  if (!(p.sigma_s > 0.0) || !std::isfinite(p.sigma_s))
    throw std::invalid_argument("sigma_s (spatial scale) must be positive, got " +
                                number_text(p.sigma_s));
}

GaussianFilterResult filter_normals_gaussian(const Positions& P, const Normals& normals,
                                             const Neighborhoods& R,
                                             const std::vector<float>& omega,
                                             const FilterNormalsGaussianParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (params.use_subneighborhood && omega.size() != n)
    throw std::invalid_argument("filter_normals_gaussian: sub-neighborhood weights missing");
  const double inv_two_sigma_sq = 1.0 / (2.0 * params.sigma_s * params.sigma_s);
  GaussianFilterResult out;
  out.normals.resize(static_cast<Eigen::Index>(n), 3);
  std::size_t empty = 0, zero = 0;

#pragma omp parallel for schedule(dynamic, 256) reduction(+ : empty, zero)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::RowVector3d pi = P.row(i);
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    bool any = false;
    auto weight = [&](std::uint32_t j) {  // single precision is plenty for a weight
      return static_cast<double>(
          std::exp(static_cast<float>(-(P.row(j) - pi).squaredNorm() * inv_two_sigma_sq)));
    };
    if (params.use_subneighborhood) {
      for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j) {
        const double o = omega[*j];
        if (!(o > 0.0)) continue;
        any = true;
        sum += o * weight(*j) * normals.row(*j);
      }
      empty += !any;
    }
    if (!any) {
      for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j)
        sum += weight(*j) * normals.row(*j);
    }
    const double norm = sum.norm();
    if (norm > 1e-12) {
      out.normals.row(i) = sum / norm;
    } else {
      out.normals.row(i) = normals.row(i);
      ++zero;
    }
  }
  out.empty_subneighborhoods = empty;
  out.zero_sum = zero;
  return out;
}

}  // namespace detexture
