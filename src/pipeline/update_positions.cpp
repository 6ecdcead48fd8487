#include "detexture/pipeline/update_positions.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "progress_counter.h"

namespace detexture {

void validate(const UpdatePositionsParams& p) {
  if (!(p.max_move >= 0.0) || !std::isfinite(p.max_move))
    throw std::invalid_argument("the largest move must be >= 0, got " + number_text(p.max_move));
  if (!(p.sigma_p > 0.0) || !std::isfinite(p.sigma_p))
    throw std::invalid_argument("sigma_p (position weight scale) must be positive, got " +
                                number_text(p.sigma_p));
  if (!(p.isotropy_deg > 0.0 && p.isotropy_deg <= 180.0))
    throw std::invalid_argument("the isotropy angle must lie in (0, 180] degrees, got " +
                                number_text(p.isotropy_deg));
  if (!(p.anchor_surface >= 0.0))
    throw std::invalid_argument("the surface anchor weight cannot be negative");
  if (!(p.anchor_texture > 0.0))
    throw std::invalid_argument("the texture anchor weight must be positive");
  if (!(p.anchor_height >= 0.0) || !std::isfinite(p.anchor_height))
    throw std::invalid_argument("the anchor height scale must be >= 0, got " +
                                number_text(p.anchor_height));
  if (!(p.anchor_angle_deg >= 0.0) || !std::isfinite(p.anchor_angle_deg))
    throw std::invalid_argument("the anchor angle scale must be >= 0 degrees (0 for none), got " +
                                number_text(p.anchor_angle_deg));
  if (!(p.solve_radius >= 0.0)) throw std::invalid_argument("the solve radius cannot be negative");
  if (p.max_iterations < 1)
    throw std::invalid_argument("the position update needs at least one iteration");
  if (!(p.tolerance > 0.0))
    throw std::invalid_argument("the position update tolerance must be positive");
}

namespace {

// Eqs. 9-10, one point at a time: neighbors stay at their input positions, so
// every point converges on its own.
UpdatePositionsResult update_local(const Positions& P, const Normals& N, const Neighborhoods& R,
                                   const UpdatePositionsParams& params, bool isotropic,
                                   const ProgressFn& progress) {
  const std::size_t n = R.size();
  const double cos_iso = std::cos(params.isotropy_deg * M_PI / 180.0);
  const double inv_two_sigma_sq = 1.0 / (2.0 * params.sigma_p * params.sigma_p);
  const double tol = params.tolerance * params.sigma_p;
  UpdatePositionsResult out;
  out.positions = P;
  std::size_t isolated = 0;
  int most = 0;
  double moved = 0.0;
  ProgressCounter counter(progress, n);
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : isolated, moved) reduction(max : most)
  for (std::size_t i = 0; i < n; ++i) {
    if ((i & 1023) == 1023) counter.advance(1024);
    const Eigen::RowVector3d ni = N.row(i);
    bool any = false;
    for (const std::uint32_t* j = R.begin(i); j != R.end(i) && !any; ++j)
      any = *j != i && (!isotropic || ni.dot(N.row(*j)) >= cos_iso);
    if (!any) {
      ++isolated;
      continue;
    }
    Eigen::RowVector3d p = P.row(i);
    int it = 0;
    while (it < params.max_iterations) {
      ++it;
      Eigen::RowVector3d step = Eigen::RowVector3d::Zero();
      double wsum = 0.0;
      for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j) {
        const auto nj = N.row(*j);
        if (isotropic && ni.dot(nj) < cos_iso) continue;
        const Eigen::RowVector3d d = P.row(*j) - p;
        const double w = std::exp(-d.squaredNorm() * inv_two_sigma_sq);
        step += w * d.dot(nj) * nj;
        wsum += w;
      }
      if (wsum <= 0.0) break;
      step /= wsum;
      p += step;
      if (step.norm() < tol) break;
    }
    most = std::max(most, it);
    moved += (p - P.row(i)).norm();
    out.positions.row(i) = p;
  }
  counter.advance(n);
  out.isolated = isolated;
  out.iterations = most;
  out.mean_displacement = n ? moved / static_cast<double>(n) : 0.0;
  return out;
}

// The global solve along the normals (see the header). Row i of the system
// lists the members of Ψ_i within the solve radius: a prefix of R_i, which is
// sorted by distance, filtered by normal angle. Both conditions are
// symmetric, so the matrix is too.
UpdatePositionsResult update_global(const Positions& P, const Normals& N, const Neighborhoods& R,
                                    const std::vector<std::uint8_t>& is_texture,
                                    const std::vector<float>& height, const Normals& input_normals,
                                    const std::vector<float>& anchor_scale,
                                    const UpdatePositionsParams& params,
                                    const ProgressFn& progress) {
  const std::size_t n = R.size();
  if (is_texture.size() != n)
    throw std::invalid_argument("update_positions: the global update needs texture labels");
  const double cos_iso = std::cos(params.isotropy_deg * M_PI / 180.0);
  const double inv_two_sigma_sq = 1.0 / (2.0 * params.sigma_p * params.sigma_p);
  const double radius_sq = params.solve_radius > 0.0 ? params.solve_radius * params.solve_radius
                                                     : std::numeric_limits<double>::infinity();

  // Row lengths (prefix of R_i inside the solve radius), then coefficients.
  std::vector<std::uint64_t> offsets(n + 1, 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t len = 0;
    for (const std::uint32_t* j = R.begin(i); j != R.end(i); ++j, ++len)
      if ((P.row(*j) - P.row(i)).squaredNorm() > radius_sq) break;
    offsets[i + 1] = len;
  }
  for (std::size_t i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
  std::vector<float> off_diag(offsets[n], 0.0f);  // A_ij = -w a b (0: not in Ψ_i, or self)
  Eigen::VectorXd diag(static_cast<Eigen::Index>(n)), rhs(static_cast<Eigen::Index>(n));
  std::size_t isolated = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : isolated)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::RowVector3d ni = N.row(i), pi = P.row(i);
    double data = 0.0, b_i = 0.0;
    const std::uint32_t* nb = R.begin(i);
    for (std::uint64_t e = offsets[i]; e < offsets[i + 1]; ++e, ++nb) {
      const std::uint32_t j = *nb;
      if (j == i) continue;
      const Eigen::RowVector3d nj = N.row(j);
      if (ni.dot(nj) < cos_iso) continue;
      const Eigen::RowVector3d mid = (ni + nj).normalized();
      const Eigen::RowVector3d d = pi - P.row(j);
      const double w = std::exp(-d.squaredNorm() * inv_two_sigma_sq);
      const double a = ni.dot(mid), b = nj.dot(mid), c = d.dot(mid);
      data += w * a * a;
      off_diag[e] = static_cast<float>(-w * a * b);
      b_i -= w * a * c;
    }
    double beta = is_texture[i] ? params.anchor_texture : params.anchor_surface;
    if (!is_texture[i] && (params.anchor_height > 0.0 || params.anchor_angle_deg > 0.0)) {
      // A surface point off its own fitted surface (noise, the flank of a
      // wave), or tilted against the filtered normals (the foot of a bump),
      // is held less: its input position is not the surface either.
      double e = 0.0;
      if (params.anchor_height > 0.0) {
        const double q = height[i] / params.anchor_height;
        e += q * q;
      }
      // A point without a usable input normal (zero) gives no evidence.
      if (params.anchor_angle_deg > 0.0 && input_normals.row(i).squaredNorm() > 0.0) {
        const double c = std::clamp(input_normals.row(i).dot(ni), -1.0, 1.0);
        const double q = std::acos(c) * (180.0 / M_PI) / params.anchor_angle_deg;
        e += q * q;
      }
      beta = params.anchor_texture +
             (params.anchor_surface - params.anchor_texture) * std::exp(-0.5 * e);
    }
    if (!anchor_scale.empty()) beta *= anchor_scale[i];
    if (data <= 0.0) {
      ++isolated;
      data = 1.0;  // decoupled row: t_i = 0, the point stays
    }
    diag(static_cast<Eigen::Index>(i)) = data * (1.0 + beta);
    rhs(static_cast<Eigen::Index>(i)) = b_i;
  }

  // Jacobi-preconditioned conjugate gradients from t = 0, three parallel
  // loops per step over fixed blocks of rows. Dot products are summed per
  // block and then in block order, so the result does not depend on the
  // number of threads; few parallel regions keep idle threads from spinning.
  constexpr std::size_t kBlock = 4096;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> t(n, 0.0), r(n), z(n), p(n), Ap(n), inv_diag(n);
  std::vector<double> part_a(blocks), part_b(blocks);
  auto block_sum = [](const std::vector<double>& part) {
    double s = 0.0;
    for (double v : part) s += v;
    return s;
  };
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < blocks; ++k) {
    double rz = 0.0, bb = 0.0;
    for (std::size_t i = k * kBlock; i < std::min(n, (k + 1) * kBlock); ++i) {
      inv_diag[i] = 1.0 / diag(static_cast<Eigen::Index>(i));
      r[i] = rhs(static_cast<Eigen::Index>(i));
      z[i] = p[i] = inv_diag[i] * r[i];
      rz += r[i] * z[i];
      bb += r[i] * r[i];
    }
    part_a[k] = rz;
    part_b[k] = bb;
  }
  double rz = block_sum(part_a), rr = block_sum(part_b);
  const double stop = params.tolerance * std::sqrt(rr);
  int it = 0;
  while (it < params.max_iterations && std::sqrt(rr) > stop) {
    ++it;
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < blocks; ++k) {  // Ap = A p, and p·Ap
      double pAp = 0.0;
      for (std::size_t i = k * kBlock; i < std::min(n, (k + 1) * kBlock); ++i) {
        double s = diag(static_cast<Eigen::Index>(i)) * p[i];
        const std::uint32_t* nb = R.begin(i);
        for (std::uint64_t e = offsets[i]; e < offsets[i + 1]; ++e, ++nb)
          s += static_cast<double>(off_diag[e]) * p[*nb];
        Ap[i] = s;
        pAp += p[i] * s;
      }
      part_a[k] = pAp;
    }
    const double alpha = rz / block_sum(part_a);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < blocks; ++k) {  // t, r, z, and r·z, r·r
      double rz_k = 0.0, rr_k = 0.0;
      for (std::size_t i = k * kBlock; i < std::min(n, (k + 1) * kBlock); ++i) {
        t[i] += alpha * p[i];
        r[i] -= alpha * Ap[i];
        z[i] = inv_diag[i] * r[i];
        rz_k += r[i] * z[i];
        rr_k += r[i] * r[i];
      }
      part_a[k] = rz_k;
      part_b[k] = rr_k;
    }
    const double rz_next = block_sum(part_a);
    rr = block_sum(part_b);
    const double beta = rz_next / rz;
    rz = rz_next;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    if (progress) progress(static_cast<double>(it) / params.max_iterations);
  }
  if (progress) progress(1.0);

  UpdatePositionsResult out;
  out.positions = P;
  double moved = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    out.positions.row(i) += t[i] * N.row(i);
    moved += std::abs(t[i]);
  }
  out.iterations = it;
  out.isolated = isolated;
  out.mean_displacement = n ? moved / static_cast<double>(n) : 0.0;
  return out;
}

}  // namespace

UpdatePositionsResult update_positions(const Positions& P, const Normals& filtered,
                                       const Neighborhoods& R,
                                       const std::vector<std::uint8_t>& is_texture,
                                       const UpdatePositionsParams& params,
                                       const ProgressFn& progress) {
  return update_positions(P, filtered, R, is_texture, {}, params, progress);
}

UpdatePositionsResult update_positions(const Positions& P, const Normals& filtered,
                                       const Neighborhoods& R,
                                       const std::vector<std::uint8_t>& is_texture,
                                       const std::vector<float>& height,
                                       const UpdatePositionsParams& params,
                                       const ProgressFn& progress) {
  return update_positions(P, filtered, R, is_texture, height, Normals(), params, progress);
}

UpdatePositionsResult update_positions(
    const Positions& P, const Normals& filtered, const Neighborhoods& R,
    const std::vector<std::uint8_t>& is_texture, const std::vector<float>& height,
    const Normals& input_normals, const UpdatePositionsParams& params, const ProgressFn& progress) {
  return update_positions(P, filtered, R, is_texture, height, input_normals, {}, params, progress);
}

UpdatePositionsResult update_positions(
    const Positions& P, const Normals& filtered, const Neighborhoods& R,
    const std::vector<std::uint8_t>& is_texture, const std::vector<float>& height,
    const Normals& input_normals, const std::vector<float>& anchor_scale,
    const UpdatePositionsParams& params, const ProgressFn& progress) {
  validate(params);
  if (static_cast<std::size_t>(P.rows()) != R.size() || filtered.rows() != P.rows())
    throw std::invalid_argument(
        "update_positions: positions, normals and neighborhoods differ in size");
  if (params.mode == UpdateMode::Global && params.anchor_height > 0.0 &&
      height.size() != static_cast<std::size_t>(P.rows()))
    throw std::invalid_argument(
        "update_positions: anchor_height needs the height of every point (" +
        std::to_string(P.rows()) + "), got " + std::to_string(height.size()));
  if (params.mode == UpdateMode::Global && params.anchor_angle_deg > 0.0 &&
      input_normals.rows() != P.rows())
    throw std::invalid_argument(
        "update_positions: anchor_angle_deg needs the input normal of every point (" +
        std::to_string(P.rows()) + "), got " + std::to_string(input_normals.rows()));
  if (!anchor_scale.empty() && anchor_scale.size() != static_cast<std::size_t>(P.rows()))
    throw std::invalid_argument("update_positions: anchor_scale needs one factor per point (" +
                                std::to_string(P.rows()) + "), got " +
                                std::to_string(anchor_scale.size()));
  for (float f : anchor_scale)
    if (!(f >= 0.0f) || !std::isfinite(f))
      throw std::invalid_argument(
          "update_positions: every anchor_scale factor must be finite and >= 0, got " +
          number_text(f));
  UpdatePositionsResult out;
  switch (params.mode) {
    case UpdateMode::Global:
      out = update_global(P, filtered, R, is_texture, height, input_normals, anchor_scale, params,
                          progress);
      break;
    case UpdateMode::Isotropic:
      out = update_local(P, filtered, R, params, true, progress);
      break;
    case UpdateMode::Eq9:
      out = update_local(P, filtered, R, params, false, progress);
      break;
    default:
      throw std::logic_error("update_positions: unknown mode");
  }
  if (params.max_move > 0.0) {
    const std::size_t n = static_cast<std::size_t>(P.rows());
    double moved = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::RowVector3d step = out.positions.row(i) - P.row(i);
      const double length = step.norm();
      if (length > params.max_move) {
        out.positions.row(i) = P.row(i) + step * (params.max_move / length);
        ++out.limited;
      }
      moved += std::min(length, params.max_move);
    }
    out.mean_displacement = n ? moved / static_cast<double>(n) : 0.0;
  }
  return out;
}

}  // namespace detexture
