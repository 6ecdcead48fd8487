#include "detexture/pipeline/estimate_texture_scale.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "detexture/geometry/drop_opposite_neighbors.h"
#include "detexture/geometry/point_index.h"
#include "random.h"

namespace detexture {

void validate(const EstimateTextureScaleParams& p) {
  if (p.samples < 10) throw std::invalid_argument("the scale estimate needs at least 10 samples");
  if (p.spacing_neighbors < 3)
    throw std::invalid_argument("the spacing estimate needs at least 3 neighbors");
  if (!(p.min_radius > 1.0) || !std::isfinite(p.min_radius))
    throw std::invalid_argument("the smallest fit radius must exceed one point spacing");
  if (!(p.max_radius > 0.0 && p.max_radius <= 0.5))
    throw std::invalid_argument("the largest fit radius must be in (0, 0.5] of the diagonal");
  if (p.radii < 4) throw std::invalid_argument("the scale estimate needs at least 4 radii");
  if (p.max_fit_points < 16)
    throw std::invalid_argument("a fit needs at least 16 points to thin to");
  if (!(p.rise_fraction > 0.0 && p.rise_fraction < 1.0))
    throw std::invalid_argument("the rise fraction must be in (0, 1)");
  if (!(p.max_end_slope > 0.0))
    throw std::invalid_argument("the largest end slope must be positive");
  if (!(p.thin_share > 0.0 && p.thin_share < 1.0))
    throw std::invalid_argument("the thin-part share must be in (0, 1)");
  if (!(p.thin_angle_deg > 90.0 && p.thin_angle_deg <= 180.0))
    throw std::invalid_argument("the thin-part angle must be in (90, 180] degrees");
  if (!(p.plateau_slope >= 0.0) || !std::isfinite(p.plateau_slope))
    throw std::invalid_argument("the plateau slope must be >= 0 (0: read the whole curve)");
  if (!(p.curved_plateau_slope >= 0.0) || !std::isfinite(p.curved_plateau_slope))
    throw std::invalid_argument(
        "the curved plateau slope must be >= 0 (0: only plateau_slope marks a plateau)");
  if (!(p.curved_end_slope > 0.0) || !std::isfinite(p.curved_end_slope))
    throw std::invalid_argument("the curved plateau's end slope must be positive");
  if (!(p.radius_calibration > 0.0) || !(p.min_relief >= 0.0) || !(p.min_noise_ratio >= 0.0))
    throw std::invalid_argument("the scale calibration and thresholds must be positive");
}

namespace {

// The m points with the smallest hash of (seed, coordinates): independent of
// the order of the points.
std::vector<std::uint32_t> choose_samples(const Positions& P, std::size_t m, std::uint64_t seed) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t h = splitmix64_mix(seed + 0x9E3779B97F4A7C15ull);
    for (int c = 0; c < 3; ++c) {
      std::uint64_t bits;
      const double v = P(i, c) == 0.0 ? 0.0 : P(i, c);  // -0 and +0 alike
      std::memcpy(&bits, &v, sizeof bits);
      h = splitmix64_mix(h ^ bits);
    }
    keys[i] = {h, static_cast<std::uint32_t>(i)};
  }
  m = std::min(m, n);
  std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(m), keys.end());
  keys.resize(m);
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint32_t> out(m);
  for (std::size_t k = 0; k < m; ++k) out[k] = keys[k].second;
  return out;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t h = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(h), v.end());
  return v[h];
}

struct Fit {
  double rms = 0.0, range = 0.0;
  bool ok = false;
};

// Plane by PCA, then a quadric height field over it, by least squares.
Fit fit_quadric(const std::vector<Eigen::Vector3d>& Q, double radius) {
  Fit fit;
  const std::size_t n = Q.size();
  if (n < 10) return fit;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& q : Q) c += q;
  c /= static_cast<double>(n);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const auto& q : Q) C += (q - c) * (q - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(C);
  const Eigen::Vector3d w = eig.eigenvectors().col(0);
  const Eigen::Vector3d u = eig.eigenvectors().col(2);
  const Eigen::Vector3d v = w.cross(u);
  // Coordinates scaled by 1/radius, so the normal equations are well conditioned.
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Matrix<double, 6, 1>> rows(n);
  std::vector<double> z(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d d = (Q[k] - c) / radius;
    const double x = d.dot(u), y = d.dot(v);
    z[k] = d.dot(w);
    rows[k] << 1.0, x, y, x * x, x * y, y * y;
    A.selfadjointView<Eigen::Lower>().rankUpdate(rows[k]);
    b += rows[k] * z[k];
  }
  A = A.selfadjointView<Eigen::Lower>();
  A.diagonal().array() += 1e-12 * static_cast<double>(n);
  const Eigen::Matrix<double, 6, 1> a = A.ldlt().solve(b);
  double ss = 0.0, lo = 0.0, hi = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double e = z[k] - rows[k].dot(a);
    ss += e * e;
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  fit.rms = radius * std::sqrt(ss / static_cast<double>(n - 6));
  fit.range = radius * (hi - lo);
  fit.ok = std::isfinite(fit.rms);
  return fit;
}

// log-linear interpolation of the radius where T crosses `level` between j-1 and j.
double crossing(const std::vector<double>& r, const std::vector<double>& T, std::size_t j,
                double level) {
  if (j == 0) return r[0];
  const double t0 = T[j - 1], t1 = T[j];
  const double f = t1 > t0 ? std::clamp((level - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
  return std::exp(std::log(r[j - 1]) + f * (std::log(r[j]) - std::log(r[j - 1])));
}

std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

TextureScaleEstimate estimate_texture_scale(const Positions& P, const Normals& N,
                                            const EstimateTextureScaleParams& params) {
  validate(params);
  if (N.rows() != 0 && N.rows() != P.rows())
    throw std::invalid_argument("there must be as many normals as points, or none");
  TextureScaleEstimate est;
  const std::size_t n = static_cast<std::size_t>(P.rows());
  const double diagonal = bounding_box_diagonal(P);
  if (n < 20 || !(diagonal > 0.0)) {
    est.reason = "too few points (or no extent) to estimate a scale";
    return est;
  }
  const std::vector<std::uint32_t> samples =
      choose_samples(P, static_cast<std::size_t>(params.samples), params.seed);
  const std::size_t m = samples.size();
  est.samples = m;
  const PointIndex index(P);

  // 1. Spacing.
  const std::size_t k = static_cast<std::size_t>(params.spacing_neighbors);
  std::vector<double> spacing(m, 0.0);
#pragma omp parallel
  {
    std::vector<std::uint32_t> idx;
    std::vector<double> d2;
#pragma omp for schedule(static)
    for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(m); ++s) {
      const double q[3] = {P(samples[s], 0), P(samples[s], 1), P(samples[s], 2)};
      index.nearest(q, k + 1, idx, d2);  // the point itself comes first
      spacing[s] = std::sqrt(d2.back()) * std::sqrt(M_PI / static_cast<double>(d2.size() - 1));
    }
  }
  est.spacing = median(spacing);
  if (!(est.spacing > 0.0)) {
    est.reason = "most points coincide with their neighbors; no spacing to measure";
    return est;
  }

  // 2. Residual curve.
  const double r0 = params.min_radius * est.spacing, r1 = params.max_radius * diagonal;
  if (r1 < 2.0 * r0) {
    est.reason = "the cloud is too sparse for a multi-scale analysis (spacing " +
                 text(est.spacing) + " against a diagonal of " + text(diagonal) + ")";
    est.noise = 0.0;
    return est;
  }
  const std::size_t J = static_cast<std::size_t>(params.radii);
  est.radii.resize(J);
  for (std::size_t j = 0; j < J; ++j)
    est.radii[j] = r0 * std::pow(r1 / r0, static_cast<double>(j) / static_cast<double>(J - 1));
  std::vector<double> rms(m * J, -1.0), range(m * J, -1.0);
  const bool have_normals = N.rows() == P.rows();
  // Squared distance from each sample to the back of a thin part (step 5).
  std::vector<double> back_sq(m, std::numeric_limits<double>::infinity());
  const double thin_cos = std::cos(params.thin_angle_deg * M_PI / 180.0);
  const std::size_t cap = static_cast<std::size_t>(params.max_fit_points);
#pragma omp parallel
  {
    std::vector<std::pair<std::uint32_t, double>> found;
    std::vector<Eigen::Vector3d> Q;
#pragma omp for schedule(dynamic, 8)
    for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(m); ++s) {
      const std::uint32_t i = samples[s];
      const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
      index.within(q, r1, found);
      if (have_normals) {
        const Eigen::RowVector3d ni = N.row(i), pi = P.row(i);
        for (const auto& [j, d2] : found) {
          const Eigen::RowVector3d nj = N.row(j), d = P.row(j) - pi;
          if (is_back_of_part(ni, nj, d, thin_cos)) back_sq[s] = std::min(back_sq[s], d2);
        }
        found.erase(std::remove_if(found.begin(), found.end(),
                                   [&](const auto& f) { return N.row(f.first).dot(ni) < 0.0; }),
                    found.end());
      }
      // Ties broken by position, not index, so that the order of the points
      // does not matter.
      std::sort(found.begin(), found.end(), [&P](const auto& a, const auto& b) {
        if (a.second != b.second) return a.second < b.second;
        for (int c = 0; c < 3; ++c)
          if (P(a.first, c) != P(b.first, c)) return P(a.first, c) < P(b.first, c);
        return false;
      });
      std::size_t end = 0;
      for (std::size_t j = 0; j < J; ++j) {
        const double radius_sq = est.radii[j] * est.radii[j];
        while (end < found.size() && found[end].second <= radius_sq) ++end;
        const std::size_t take = std::min(end, cap);
        Q.resize(take);
        for (std::size_t t = 0; t < take; ++t) {
          const std::uint32_t p = found[t * end / take].first;
          Q[t] = P.row(p).transpose();
        }
        const Fit fit = fit_quadric(Q, est.radii[j]);
        if (fit.ok) {
          rms[s * J + j] = fit.rms;
          range[s * J + j] = fit.range;
        }
      }
    }
  }
  est.residual.assign(J, 0.0);
  est.relief.assign(J, 0.0);
  for (std::size_t j = 0; j < J; ++j) {
    std::vector<double> e, g;
    for (std::size_t s = 0; s < m; ++s)
      if (rms[s * J + j] >= 0.0) {
        e.push_back(rms[s * J + j]);
        g.push_back(range[s * J + j]);
      }
    est.residual[j] = median(e);
    est.relief[j] = median(g);
  }

  // 5. Thin parts (computed here, used by choose_radius).
  if (have_normals) {
    std::sort(back_sq.begin(), back_sq.end());
    const std::size_t at = static_cast<std::size_t>(params.thin_share * static_cast<double>(m));
    if (at < m && std::isfinite(back_sq[at])) est.thin_radius = std::sqrt(back_sq[at]);
  }

  // 3. Reading the curve.
  est.noise = est.residual[0];
  std::vector<double> T(J);
  for (std::size_t j = 0; j < J; ++j)
    T[j] = std::sqrt(std::max(0.0, est.residual[j] * est.residual[j] - est.noise * est.noise));
  // The radius is read on the peak-to-valley relief G (above its value at the
  // smallest radius, the noise's), which reaches its full height as soon as
  // a neighborhood spans a whole feature; the RMS T decides whether there is
  // texture at all. Both are read up to `last`: the whole curve, or the end
  // of the texture's plateau when the curve has one (below).
  std::vector<double> G(J);
  for (std::size_t j = 0; j < J; ++j) G[j] = std::max(0.0, est.relief[j] - est.relief[0]);
  struct Reading {
    double read = 0.0, tmax = 0.0;
    std::size_t jmax = 0;
  };
  auto read_up_to = [&](std::size_t last) {
    Reading out;
    const double gmax = *std::max_element(G.begin(), G.begin() + last + 1);
    std::size_t jr = 0;
    while (jr < J && G[jr] < params.rise_fraction * gmax) ++jr;
    out.read = crossing(est.radii, G, std::min(jr, J - 1), params.rise_fraction * gmax);
    out.jmax =
        static_cast<std::size_t>(std::max_element(T.begin(), T.begin() + last + 1) - T.begin());
    out.tmax = T[out.jmax];
    return out;
  };
  auto has_relief = [&](const Reading& g) {
    return g.tmax > params.min_relief * g.read && g.tmax > params.min_noise_ratio * est.noise;
  };
  // The log-log slope of a curve over the radii from step a to step b.
  auto log_slope = [&](const std::vector<double>& y, std::size_t a, std::size_t b) {
    return std::log(y[b] / y[a]) / std::log(est.radii[b] / est.radii[a]);
  };
  // The plateau: on a curved base (limbs, tubes, a body) G rises with the
  // texture, levels off once r spans the features, and rises again as the
  // base bends away from the quadric; its largest value is then the base's,
  // and reading at a share of it put r at 2.5-3.3 × the hand-set one on the
  // real-shape suite. The flattest step of G (least log-log slope) marks the
  // plateau when its slope is below `plateau_slope`; the curve is read up to
  // its end, provided the relief there is texture (the tests below). On a
  // flat or gently curved base the flattest step is at the large radii and
  // this reads the whole curve, as before. Where the base's growth starts
  // before the texture has quite levelled off (sparse texture on a base
  // curved nearly as tightly as r), the flattest step is steeper; it still
  // marks the plateau when the curve ends rising as a base does, faster
  // than r^curved_end_slope (curved_plateau_slope).
  std::size_t flattest = 0;
  double least_slope = std::numeric_limits<double>::infinity();
  for (std::size_t j = 1; j + 1 < J; ++j) {
    if (!(G[j] > 0.0) || !(G[j + 1] > 0.0)) continue;
    const double slope = log_slope(G, j, j + 1);
    if (slope < least_slope) {
      least_slope = slope;
      flattest = j;
    }
  }
  const double end_rise = G[J - 3] > 0.0 ? log_slope(G, J - 3, J - 1) : 0.0;
  const bool plateau =
      least_slope < params.plateau_slope ||
      (least_slope < params.curved_plateau_slope && end_rise > params.curved_end_slope);
  if (plateau && flattest + 2 < J) {
    const Reading g = read_up_to(flattest + 1);
    if (has_relief(g)) {
      est.texture_found = true;
      est.texture_radius = params.radius_calibration * g.read;
      est.texture_height = G[g.jmax];
      est.reason = "relief above local quadrics grows up to radius " + text(g.read) +
                   " and levels off at " + text(g.tmax) + " RMS up to radius " +
                   text(est.radii[flattest + 1]) + " (beyond that, the shape's own curvature)";
      return est;
    }
  }
  const Reading whole = read_up_to(J - 1);
  const double read = whole.read, tmax = whole.tmax;
  const double R = params.radius_calibration * read;
  if (!has_relief(whole)) {
    est.reason = "no texture found: the relief above local quadrics stays below " +
                 text(params.min_relief) + " of the radius" +
                 (tmax <= params.min_noise_ratio * est.noise ? " and within the noise" : "") +
                 " at every radius from " + text(r0) + " to " + text(r1);
    return est;
  }
  const double end_slope = T[J - 3] > 0.0 ? log_slope(T, J - 3, J - 1) : 0.0;
  if (end_slope > params.max_end_slope) {
    est.reason = "no texture found: the relief above local quadrics grows as r^" + text(end_slope) +
                 " up to the largest radius without levelling off, as the curvature of a "
                 "shape that a quadric does not follow does, not as texture";
    return est;
  }
  est.texture_found = true;
  est.texture_radius = R;
  est.texture_height = G[whole.jmax];
  est.reason = "relief above local quadrics grows up to radius " + text(read) +
               " and levels off at " + text(tmax) + " RMS";
  return est;
}

double estimate_neighbor_count(const Positions& P, double radius, int samples, std::uint64_t seed) {
  if (P.rows() == 0 || samples < 1) return 0.0;
  const std::vector<std::uint32_t> chosen =
      choose_samples(P, static_cast<std::size_t>(samples), seed);
  // One pass over the cloud, no index: cheaper than building one for a
  // few dozen counts.
  const double radius_sq = radius * radius;
  const std::size_t m = chosen.size();
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Q(static_cast<Eigen::Index>(m), 3);
  for (std::size_t s = 0; s < m; ++s) Q.row(s) = P.row(chosen[s]);
  double total = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : total)
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const double x = P(i, 0), y = P(i, 1), z = P(i, 2);
    std::size_t c = 0;
    for (std::size_t s = 0; s < m; ++s) {
      const double dx = x - Q(s, 0), dy = y - Q(s, 1), dz = z - Q(s, 2);
      c += dx * dx + dy * dy + dz * dz <= radius_sq;
    }
    total += static_cast<double>(c);
  }
  return total / static_cast<double>(m);
}

}  // namespace detexture
