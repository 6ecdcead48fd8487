#include "detexture/pipeline/fit_normals_to_positions.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "detexture/geometry/estimate_normals.h"

namespace detexture {
namespace {

// What the main loop leaves in turn[i], besides the angle in degrees
// between a taken fit and n_i.
constexpr float kNotFitted = -1.0f;  // zero or non-finite n_i, or no usable fit: n_i kept
constexpr float kRefused = 180.0f;   // the fit turned past max_turn_deg: n_i kept
// Widths of the isotropic path's ramps (header): κ from blend_coherence to
// this much above it, ā from this many degrees below blend_isotropic_high_deg.
constexpr double kCoherenceRamp = 0.05;
constexpr double kIsotropicRampDeg = 1.0;

// Waves left (header): κ_i of the departures' scatter C, then the squared
// correlation, over p_i and its fitted neighbors within ρ, between the
// position and the departure along the scatter's main direction e.
std::uint8_t waves_left(const Positions& P, const Normals& normals, const Normals& fits,
                        const Neighborhoods& R, const std::vector<float>& turn, double radius_sq,
                        std::size_t i, const Eigen::Matrix3d& C,
                        const FitNormalsToPositionsParams& params) {
  const double trace = C.trace();
  if (!(trace > 0.0)) return 0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(C);
  if (eig.eigenvalues()(2) / trace < params.waves_coherence) return 0;
  const Eigen::RowVector3d e = eig.eigenvectors().col(2).transpose();
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
  int m = 0;
  const auto add = [&](std::size_t j) {
    const double x = (P.row(j) - P.row(i)).dot(e);
    const double y = (fits.row(j) - normals.row(j)).dot(e);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
    ++m;
  };
  add(i);
  for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
    const std::uint32_t j = *nb;
    if (j == i || turn[j] == kNotFitted || turn[j] == kRefused ||
        (P.row(j) - P.row(i)).squaredNorm() > radius_sq)
      continue;
    add(j);
  }
  const double vx = sxx - sx * sx / m, vy = syy - sy * sy / m, cxy = sxy - sx * sy / m;
  if (!(vx > 0.0 && vy > 0.0)) return 0;
  return cxy * cxy / (vx * vy) >= params.waves_linearity ? 1 : 0;
}

// A weighted plane fit of R_i's members (weights[k] for the k-th, 0 to leave
// one out), in coordinates relative to p_i and two passes around the mean
// (exact for far-from-origin clouds, as in estimate_normals): the normal,
// the scatter off the plane and across it (the smallest and the middle
// eigenvalue, λ0 and λ1, over Σw) and N = (Σw)² / Σw², the weights'
// effective count.
struct PlaneFit {
  bool ok = false;
  Eigen::RowVector3d normal = Eigen::RowVector3d::Zero();
  double off = 0.0, across = 0.0, count = 0.0;
};

PlaneFit fit_plane(const Positions& P, const Neighborhoods& R, std::size_t i,
                   const std::vector<double>& weights) {
  PlaneFit fit;
  const Eigen::RowVector3d pi = P.row(i);
  double weight = 0.0, weight_sq = 0.0;
  int count = 0;
  Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
  for (std::size_t k = 0; k < weights.size(); ++k) {
    const double wj = weights[k];
    if (!(wj > 0.0)) continue;
    weight += wj;
    weight_sq += wj * wj;
    mean += wj * (P.row(R.begin(i)[k]) - pi);
    ++count;
  }
  if (count < 3 || !(weight > 0.0)) return fit;
  mean /= weight;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (!(weights[k] > 0.0)) continue;
    const Eigen::RowVector3d q = P.row(R.begin(i)[k]) - pi - mean;
    C.noalias() += weights[k] * q.transpose() * q;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);
  if (!(std::sqrt(lambda(1)) > kMinSpreadRatio * std::sqrt(lambda(2)))) return fit;
  fit.ok = true;
  fit.normal = eig.eigenvectors().col(0).transpose().normalized();
  fit.off = lambda(0) / weight;
  fit.across = lambda(1) / weight;
  fit.count = weight * weight / weight_sq;
  return fit;
}

// The blend (header): ā_i is the mean of turn[j] over p_i and its neighbors
// within ρ that were fitted (a refused fit counts as 180°: it marks the fit
// as untrustworthy there); κ_i is the share of the largest eigenvalue in the
// trace of Σ (fit_j − n_j)(fit_j − n_j)ᵀ over the same points whose fit was
// taken. The output is the fit and n mixed by
// w_i = max(ramp(ā_i; low, high), ramp(κ_i; κ, κ + kCoherenceRamp) ·
// ramp(ā_i; isotropic_high − 1°, isotropic_high)), then normalized; ramp(x;
// a, b) is 1 at or below a and 0 at or above b. Points whose own fit was not
// taken keep n_i and are not counted.
void blend_with_filtered(const Positions& P, const Normals& normals, const Neighborhoods& R,
                         const FitNormalsToPositionsParams& params, const std::vector<float>& turn,
                         FitNormalsToPositionsResult& out) {
  const std::size_t n = R.size();
  const double radius_sq = params.radius * params.radius;
  const auto ramp = [](double x, double a, double b) {
    return std::clamp((b - x) / (b - a), 0.0, 1.0);
  };
  const bool isotropic = params.blend_coherence > 0.0;
  const bool waves = params.waves_min_deg > 0.0;
  const double iso_high = params.blend_isotropic_high_deg;
  const double iso_low = std::max(iso_high - kIsotropicRampDeg, params.blend_high_deg);
  // The fits, read by the neighbors' κ while row i is blended.
  const Normals fits = out.normals;
  out.open = out.normals;
  if (waves) out.waves.assign(n, 0);
  std::size_t count = 0, open_count = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : count, open_count)
  for (std::size_t i = 0; i < n; ++i) {
    if (turn[i] == kNotFitted || turn[i] == kRefused) continue;
    double sum = turn[i];
    int members = 1;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    if (isotropic || waves) {
      const Eigen::Vector3d d = (fits.row(i) - normals.row(i)).transpose();
      C.noalias() += d * d.transpose();
    }
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
      const std::uint32_t j = *nb;
      if (j == i || turn[j] == kNotFitted || (P.row(j) - P.row(i)).squaredNorm() > radius_sq)
        continue;
      sum += turn[j];
      ++members;
      if ((isotropic || waves) && turn[j] != kRefused) {
        const Eigen::Vector3d d = (fits.row(j) - normals.row(j)).transpose();
        C.noalias() += d * d.transpose();
      }
    }
    const double mean = sum / members;
    if (waves && mean >= params.waves_min_deg)
      out.waves[i] = waves_left(P, normals, fits, R, turn, radius_sq, i, C, params);
    double w = ramp(mean, params.blend_low_deg, params.blend_high_deg);
    if (isotropic && w < 1.0 && mean < iso_high) {
      const double trace = C.trace();
      if (trace > 0.0) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
        eig.computeDirect(C, Eigen::EigenvaluesOnly);
        const double kappa = eig.eigenvalues()(2) / trace;
        w = std::max(w,
                     ramp(kappa, params.blend_coherence, params.blend_coherence + kCoherenceRamp) *
                         ramp(mean, iso_low, iso_high));
      }
    }
    // Only rows i change, and ā and κ read the turns and fits of the main loop.
    const auto mix = [&](Normals& out_normals, double weight) {
      const Eigen::RowVector3d mixed = weight * fits.row(i) + (1.0 - weight) * normals.row(i);
      const double norm = mixed.norm();
      out_normals.row(i) = norm > 0.0 ? Eigen::RowVector3d(mixed / norm) : normals.row(i);
    };
    const double w_open = ramp(mean, params.blend_open_low_deg, params.blend_open_high_deg);
    if (w_open < 1.0) {
      ++open_count;
      mix(out.open, w_open);
    }
    if (w == 1.0) continue;
    ++count;
    mix(out.normals, w);
  }
  out.blended = count;
  out.open_blended = open_count;
}

}  // namespace

void validate(const FitNormalsToPositionsParams& p) {
  if (!(p.sigma > 0.0) || !std::isfinite(p.sigma))
    throw std::invalid_argument("the normal fit's spatial scale must be positive, got " +
                                number_text(p.sigma));
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("the normal fit's radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.range_sigma > 0.0) || !std::isfinite(p.range_sigma))
    throw std::invalid_argument("the normal fit's range scale must be positive, got " +
                                number_text(p.range_sigma));
  if (!(p.max_turn_deg > 0.0 && p.max_turn_deg <= 180.0))
    throw std::invalid_argument("the normal fit's largest turn must be in (0, 180] degrees, got " +
                                number_text(p.max_turn_deg));
  if (!(p.blend_high_deg >= 0.0 && p.blend_high_deg <= 180.0))
    throw std::invalid_argument(
        "the blend's upper angle (blend_high_deg, --blend-high) must be in [0, 180] degrees, 0 "
        "for no blend, got " +
        number_text(p.blend_high_deg));
  if (!(p.blend_low_deg >= 0.0 && p.blend_low_deg <= 180.0))
    throw std::invalid_argument(
        "the blend's lower angle (blend_low_deg, --blend-low) must be in [0, 180] degrees, got " +
        number_text(p.blend_low_deg));
  if (!(p.blend_coherence >= 0.0 && p.blend_coherence < 1.0))
    throw std::invalid_argument(
        "the blend's coherence (blend_coherence, --blend-coherence) must be in [0, 1), 0 for "
        "none, got " +
        number_text(p.blend_coherence));
  if (!(p.blend_isotropic_high_deg >= 0.0 && p.blend_isotropic_high_deg <= 180.0))
    throw std::invalid_argument(
        "the blend's isotropic angle (blend_isotropic_high_deg, --blend-isotropic-high) must be "
        "in [0, 180] degrees, got " +
        number_text(p.blend_isotropic_high_deg));
  if (!(p.waves_min_deg >= 0.0 && p.waves_min_deg <= 180.0))
    throw std::invalid_argument(
        "the least mean angle of waves left (waves_min_deg) must be in [0, 180] degrees, 0 for "
        "none, got " +
        number_text(p.waves_min_deg));
  if (!(p.waves_coherence >= 0.0 && p.waves_coherence <= 1.0))
    throw std::invalid_argument(
        "the least coherence of waves left (waves_coherence) must be in "
        "[0, 1], got " +
        number_text(p.waves_coherence));
  if (!(p.waves_linearity >= 0.0 && p.waves_linearity <= 1.0))
    throw std::invalid_argument(
        "the least linearity of waves left (waves_linearity) must be in "
        "[0, 1], got " +
        number_text(p.waves_linearity));
  if (!(p.fine_ratio >= 0.0 && p.fine_ratio < 1.0))
    throw std::invalid_argument(
        "the normal fit's fine scale (fine_ratio, --fit-fine-ratio) must be in [0, 1), 0 for "
        "none, got " +
        number_text(p.fine_ratio));
  if (!(p.fine_gamma >= 0.0) || !std::isfinite(p.fine_gamma))
    throw std::invalid_argument(
        "the normal fit's fine confidence (fine_gamma, --fit-fine-gamma) must be at least 0, got " +
        number_text(p.fine_gamma));
  if (!(p.blend_open_low_deg >= 0.0 && p.blend_open_low_deg < p.blend_open_high_deg &&
        p.blend_open_high_deg <= 180.0))
    throw std::invalid_argument(
        "the blend's open window (blend_open_low_deg, blend_open_high_deg; --blend-open-low, "
        "--blend-open-high) must satisfy 0 <= low < high <= 180 degrees, got " +
        number_text(p.blend_open_low_deg) + " and " + number_text(p.blend_open_high_deg));
  if (p.blend_high_deg > 0.0 && !(p.blend_low_deg < p.blend_high_deg))
    throw std::invalid_argument("the blend's lower angle (blend_low_deg, --blend-low, " +
                                number_text(p.blend_low_deg) +
                                ") must be below its upper angle (blend_high_deg, --blend-high, " +
                                number_text(p.blend_high_deg) + ")");
}

FitNormalsToPositionsResult fit_normals_to_positions(const Positions& P, const Normals& normals,
                                                     const Neighborhoods& R,
                                                     const FitNormalsToPositionsParams& params) {
  return fit_normals_to_positions(P, normals, normals, R, params);
}

FitNormalsToPositionsResult fit_normals_to_positions(const Positions& P, const Normals& normals,
                                                     const Normals& range_normals,
                                                     const Neighborhoods& R,
                                                     const FitNormalsToPositionsParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n || normals.rows() != P.rows() ||
      range_normals.rows() != P.rows())
    throw std::invalid_argument(
        "fit_normals_to_positions: positions, normals, range normals and neighborhoods "
        "differ in size");
  // Rows of range_normals that weigh: a pair uses them when both have one.
  std::vector<std::uint8_t> has_range(n);
  for (std::size_t i = 0; i < n; ++i)
    has_range[i] = range_normals.row(i).squaredNorm() != 0.0 && range_normals.row(i).allFinite();
  const double radius_sq = params.radius * params.radius;
  const double inv_two_sigma_sq = 1.0 / (2.0 * params.sigma * params.sigma);
  const double inv_two_range_sq = 1.0 / (2.0 * params.range_sigma * params.range_sigma);
  const double min_cos = std::cos(params.max_turn_deg * M_PI / 180.0);
  FitNormalsToPositionsResult out;
  out.normals = normals;
  std::size_t kept = 0;
  const bool blend = params.blend_high_deg > 0.0;
  std::vector<float> turn(blend ? n : 0, kNotFitted);  // see kNotFitted

  const bool fine = params.fine_ratio > 0.0;
  // Per point: a plane was fitted; the fine fit, its noise estimate σn² and
  // its λ1 N (0 where it was not fitted).
  std::vector<std::uint8_t> fitted(n, 0);
  Normals fine_normals(fine ? n : 0, 3);
  std::vector<double> noise_sq(fine ? n : 0, 0.0), fine_spread(fine ? n : 0, 0.0);
  const double inv_two_fine_sq =
      fine ? inv_two_sigma_sq / (params.fine_ratio * params.fine_ratio) : 0.0;

#pragma omp parallel reduction(+ : kept)
  {
    // w_ij of R_i's members at σ and at the fine scale, reused from point to point.
    std::vector<double> weights, fine_weights;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::RowVector3d pi = P.row(i);
      const Eigen::RowVector3d ni = normals.row(i);
      if (ni.squaredNorm() == 0.0 || !ni.allFinite()) continue;
      const Eigen::RowVector3d ri = range_normals.row(i);
      weights.assign(R.count(i), 0.0);
      if (fine) fine_weights.assign(R.count(i), 0.0);
      for (std::size_t k = 0; k < weights.size(); ++k) {
        const std::uint32_t j = R.begin(i)[k];
        const double d_sq = (P.row(j) - pi).squaredNorm();
        if (d_sq > radius_sq) continue;
        const double t = has_range[i] && has_range[j] ? 1.0 - ri.dot(range_normals.row(j))
                                                      : 1.0 - ni.dot(normals.row(j));
        const double range = t * t * inv_two_range_sq;
        weights[k] = std::exp(-d_sq * inv_two_sigma_sq - range);
        if (fine) fine_weights[k] = std::exp(-d_sq * inv_two_fine_sq - range);
      }
      const PlaneFit wide = fit_plane(P, R, i, weights);
      if (!wide.ok) {
        ++kept;
        continue;
      }
      fitted[i] = 1;
      out.normals.row(i) = wide.normal;
      if (!fine) continue;
      const PlaneFit narrow = fit_plane(P, R, i, fine_weights);
      if (!narrow.ok || !(wide.across > narrow.across)) continue;
      fine_normals.row(i) =
          narrow.normal.dot(wide.normal) < 0.0 ? Eigen::RowVector3d(-narrow.normal) : narrow.normal;
      // λ0 = σn² + c λ1 at both scales (noise plus the shape's bending).
      noise_sq[i] = std::max(0.0, (narrow.off * wide.across - wide.off * narrow.across) /
                                      (wide.across - narrow.across));
      fine_spread[i] = narrow.across * narrow.count;
    }
  }
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : kept)
  for (std::size_t i = 0; i < n; ++i) {
    if (!fitted[i]) continue;
    const Eigen::RowVector3d ni = normals.row(i);
    Eigen::RowVector3d m = out.normals.row(i);
    if (fine && fine_spread[i] > 0.0) {
      double sum = noise_sq[i];
      int members = 1;
      for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
        const std::uint32_t j = *nb;
        if (j == i || !(fine_spread[j] > 0.0) || (P.row(j) - P.row(i)).squaredNorm() > radius_sq)
          continue;
        sum += noise_sq[j];
        ++members;
      }
      const double noise = std::sqrt(sum / members / fine_spread[i]);
      const Eigen::RowVector3d fm = fine_normals.row(i);
      const double d = std::acos(std::min(fm.dot(m), 1.0));
      const double t = noise > 0.0 ? std::clamp(d / noise - params.fine_gamma, 0.0, 1.0) : 1.0;
      if (t > 0.0) m = ((1.0 - t) * m + t * fm).normalized();
    }
    double c = m.dot(ni);
    if (c < 0.0) {
      m = -m;
      c = -c;
    }
    if (c < min_cos) {
      ++kept;
      out.normals.row(i) = ni;
      if (blend) turn[i] = kRefused;
      continue;
    }
    out.normals.row(i) = m;
    if (blend) turn[i] = static_cast<float>(std::acos(std::min(c, 1.0)) * 180.0 / M_PI);
  }
  out.kept = kept;
  if (blend) blend_with_filtered(P, normals, R, params, turn, out);
  return out;
}

}  // namespace detexture
