#include "detexture/pipeline/filter_normals_rolling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const FilterNormalsRollingParams& p) {
  if (!(p.sigma_s > 0.0) || !std::isfinite(p.sigma_s))
    throw std::invalid_argument("sigma_s (spatial scale) must be positive, got " +
                                number_text(p.sigma_s));
  if (!(p.sigma_r_deg > 0.0 && p.sigma_r_deg <= 180.0))
    throw std::invalid_argument("sigma_r (range scale) must lie in (0, 180] degrees, got " +
                                number_text(p.sigma_r_deg));
  if (p.iterations < 0)
    throw std::invalid_argument("the number of rolling iterations cannot be negative, got " +
                                number_text(p.iterations));
  if (!(p.tolerance_deg >= 0.0))
    throw std::invalid_argument("the rolling tolerance cannot be negative, got " +
                                number_text(p.tolerance_deg));
}

RollingFilterResult filter_normals_rolling(const Positions& P, const Normals& input,
                                           Normals initial, const Neighborhoods& R,
                                           const std::vector<float>& omega,
                                           const FilterNormalsRollingParams& params,
                                           const ProgressFn& progress) {
  validate(params);
  const std::size_t n = R.size();
  const bool sub = params.use_subneighborhood;
  if (sub && omega.size() != n)
    throw std::invalid_argument("filter_normals_rolling: sub-neighborhood weights missing");
  const double inv_two_sigma_s_sq = 1.0 / (2.0 * params.sigma_s * params.sigma_s);
  const double chord = 2.0 * std::sin(params.sigma_r_deg * M_PI / 360.0);
  const double inv_two_chord_sq = 1.0 / (2.0 * chord * chord);

  RollingFilterResult out;
  out.normals = std::move(initial);
  // Eq. 3 reads its neighbors' guidance and input normals, and N^k only at
  // i itself, so N^{k+1} is written over N^k in place: one array less at the
  // method's peak memory.
  const double* p = P.data();
  const double* nin = input.data();
  const float* member = sub ? omega.data() : nullptr;
  for (int k = 0; k < params.iterations; ++k) {
    const Normals G = guidance_normals(P, out.normals, R, params.guidance);
    const double* g = G.data();
    double change = 0.0;
#pragma omp parallel for schedule(dynamic, 512) reduction(+ : change)
    for (std::size_t i = 0; i < n; ++i) {
      const double px = p[3 * i], py = p[3 * i + 1], pz = p[3 * i + 2];
      const double gx = g[3 * i], gy = g[3 * i + 1], gz = g[3 * i + 2];
      double sx = 0.0, sy = 0.0, sz = 0.0;
      bool any = false;
      // Pass 0 sums over Ω_i; pass 1, over R_i (the paper, or an empty Ω_i).
      for (int pass = member ? 0 : 1; pass < 2 && !any; ++pass) {
        for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it) {
          const std::size_t j = *it;
          const double o = pass == 0 ? member[j] : 1.0;
          if (!(o > 0.0)) continue;
          const double dx = p[3 * j] - px, dy = p[3 * j + 1] - py, dz = p[3 * j + 2] - pz;
          const double ex = g[3 * j] - gx, ey = g[3 * j + 1] - gy, ez = g[3 * j + 2] - gz;
          // Single-precision exp: the weight needs no more, and it is the
          // costliest operation of the method (one per pair and iteration).
          const double w =
              o * std::exp(static_cast<float>(-(dx * dx + dy * dy + dz * dz) * inv_two_sigma_s_sq -
                                              (ex * ex + ey * ey + ez * ez) * inv_two_chord_sq));
          sx += w * nin[3 * j];
          sy += w * nin[3 * j + 1];
          sz += w * nin[3 * j + 2];
          any = true;
        }
      }
      const double norm = std::sqrt(sx * sx + sy * sy + sz * sz);
      if (norm > 1e-12) {
        const Eigen::RowVector3d next(sx / norm, sy / norm, sz / norm);
        change += std::acos(std::clamp(next.dot(out.normals.row(i)), -1.0, 1.0));
        out.normals.row(i) = next;
      }
    }
    out.iterations = k + 1;
    out.last_change_deg = n ? change / static_cast<double>(n) * 180.0 / M_PI : 0.0;
    if (progress) progress(static_cast<double>(k + 1) / params.iterations);
    if (out.last_change_deg < params.tolerance_deg) break;
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace detexture
