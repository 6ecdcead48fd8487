#include "detexture/pipeline/detect_texture.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

#include "progress_counter.h"
#include "random.h"

namespace detexture {
namespace {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;  // plane: normal . q = offset
  double distance(const Eigen::Vector3d& q) const { return std::abs(normal.dot(q) - offset); }
};

// RANSAC tries needed to draw an all-inlier triple with the given confidence
// when a fraction w of the points are inliers.
double tries_needed(double w, double confidence) {
  const double all_in = w * w * w;
  if (all_in >= 1.0 - 1e-12) return 1.0;
  if (all_in <= 0.0) return 1e18;
  return std::log(1.0 - confidence) / std::log(1.0 - all_in);
}

// RANSAC with adaptive termination over the points Q[subset], then an
// optional least-squares refit to the inliers. count is 0 when no
// non-degenerate triple was found.
struct PlaneFit {
  Plane plane;
  std::size_t count = 0;
  int tries = 0;
};

Plane least_squares_plane(const std::vector<Eigen::Vector3d>& Q,
                          const std::vector<std::uint32_t>& subset, const Plane& plane,
                          double lambda, std::size_t count, bool* ok) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const std::uint32_t t : subset)
    if (plane.distance(Q[t]) < lambda) mean += Q[t];
  mean /= static_cast<double>(count);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const std::uint32_t t : subset)
    if (plane.distance(Q[t]) < lambda) cov.noalias() += (Q[t] - mean) * (Q[t] - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Plane refined;
  refined.normal = eig.eigenvectors().col(0);
  refined.offset = refined.normal.dot(mean);
  *ok = eig.eigenvalues()(1) > 0.0;
  return refined;
}

// min_count: a plane with fewer inliers is of no use to the caller, so once
// enough tries have been made to find such a plane at the chosen confidence,
// RANSAC gives up (the further planes of curved texture would otherwise run
// to the cap).
PlaneFit fit_plane(const std::vector<Eigen::Vector3d>& Q, const std::vector<std::uint32_t>& subset,
                   double extent_sq, const DetectTextureParams& params, SplitMix64& rng,
                   double min_count) {
  const std::uint32_t k = static_cast<std::uint32_t>(subset.size());
  // A triple whose cross product is this small is collinear for our purposes.
  const double min_cross = 1e-12 * extent_sq;
  auto count_in = [&](const Plane& plane) {
    std::size_t c = 0;
    for (const std::uint32_t t : subset) c += plane.distance(Q[t]) < params.lambda;
    return c;
  };
  PlaneFit fit;
  double needed = std::min<double>(
      params.max_iterations,
      tries_needed(std::min(1.0, min_count / static_cast<double>(k)), params.confidence));
  while (fit.tries < params.max_iterations && fit.tries < needed) {
    ++fit.tries;
    const std::uint32_t a = rng.below(k);
    std::uint32_t b = rng.below(k - 1);
    b += (b >= a);
    std::uint32_t c = rng.below(k - 2);
    const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
    c += (c >= lo);
    c += (c >= hi);
    const Eigen::Vector3d& qa = Q[subset[a]];
    const Eigen::Vector3d cross = (Q[subset[b]] - qa).cross(Q[subset[c]] - qa);
    const double norm = cross.norm();
    if (norm <= min_cross) continue;
    Plane plane;
    plane.normal = cross / norm;
    plane.offset = plane.normal.dot(qa);
    const std::size_t count = count_in(plane);
    if (count > fit.count) {
      fit.count = count;
      fit.plane = plane;
      needed = std::min(needed, tries_needed(static_cast<double>(count) / k, params.confidence));
    }
  }
  if (params.refine && fit.count >= 3) {
    bool ok = false;
    const Plane refined = least_squares_plane(Q, subset, fit.plane, params.lambda, fit.count, &ok);
    if (ok) {
      const std::size_t count = count_in(refined);
      if (count >= fit.count) {
        fit.plane = refined;
        fit.count = count;
      }
    }
  }
  return fit;
}

}  // namespace

void validate(const DetectTextureParams& p) {
  if (!(p.lambda > 0.0) || !std::isfinite(p.lambda))
    throw std::invalid_argument("lambda (RANSAC distance threshold) must be positive, got " +
                                number_text(p.lambda));
  if (!(p.delta > 0.0 && p.delta < 1.0))
    throw std::invalid_argument("delta (inlier proportion) must lie in (0, 1), got " +
                                number_text(p.delta));
  if (!(p.confidence > 0.0 && p.confidence < 1.0))
    throw std::invalid_argument("the RANSAC confidence must lie in (0, 1), got " +
                                number_text(p.confidence));
  if (p.planes < 1 || p.planes > 3)
    throw std::invalid_argument("the number of planes per neighborhood must be 1, 2 or 3, got " +
                                number_text(p.planes));
  if (!(p.second_plane_share > 0.0 && p.second_plane_share < 1.0))
    throw std::invalid_argument("the second plane's share must lie in (0, 1), got " +
                                number_text(p.second_plane_share));
  if (!(p.second_plane_angle_deg > 0.0 && p.second_plane_angle_deg <= 90.0))
    throw std::invalid_argument("the second plane's angle must lie in (0, 90] degrees, got " +
                                number_text(p.second_plane_angle_deg));
  if (p.max_iterations < 1)
    throw std::invalid_argument("the RANSAC iteration cap must be at least 1, got " +
                                number_text(p.max_iterations));
}

TextureDetection detect_texture(const Positions& P, const Neighborhoods& R,
                                const DetectTextureParams& params, const ProgressFn& progress) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument("detect_texture: positions and neighborhoods differ in size");
  TextureDetection out;
  out.inliers.assign(n, 0);
  out.members.assign(n, 0);
  std::uint32_t* T = out.inliers.data();
  std::uint32_t* N = out.members.data();
  std::size_t no_plane = 0;
  double total_tries = 0.0;
  ProgressCounter counter(progress, n);
  const double cos_second_angle = std::cos(params.second_plane_angle_deg * M_PI / 180.0);

#pragma omp parallel reduction(+ : no_plane, total_tries)
  {
    std::vector<Eigen::Vector3d> Q;     // neighbors, relative to p_i
    std::vector<std::uint32_t> subset;  // candidates of the plane being fitted
    std::vector<std::uint8_t> inlier;   // per neighbor: fits one of the planes
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      if ((i & 1023) == 1023) counter.advance(1024);
      const std::uint32_t k = static_cast<std::uint32_t>(R.count(i));
      const std::uint32_t* nb = R.begin(i);
      if (k < 3) {
        ++no_plane;
        continue;
      }
      const Eigen::Vector3d center = P.row(i).transpose();
      Q.resize(k);
      double extent_sq = 0.0;
      for (std::uint32_t t = 0; t < k; ++t) {
        Q[t] = P.row(nb[t]).transpose() - center;
        extent_sq = std::max(extent_sq, Q[t].squaredNorm());
      }
      SplitMix64 rng(params.seed, i);
      subset.resize(k);
      for (std::uint32_t t = 0; t < k; ++t) subset[t] = t;
      const PlaneFit first = fit_plane(Q, subset, extent_sq, params, rng, 3.0);
      total_tries += first.tries;
      if (first.count == 0) {
        ++no_plane;
        continue;
      }
      inlier.assign(k, 0);
      subset.clear();
      for (std::uint32_t t = 0; t < k; ++t) {
        inlier[t] = first.plane.distance(Q[t]) < params.lambda;
        if (!inlier[t]) subset.push_back(t);
      }
      // Further planes at an angle to every earlier one, each with a real
      // share of the neighborhood, are the other faces of a crease or corner:
      // their points are surface.
      const double min_share = params.second_plane_share * k;
      Eigen::Vector3d normals_found[3] = {first.plane.normal};
      for (int plane = 1; plane < params.planes; ++plane) {
        if (subset.size() < std::max(3.0, min_share)) break;
        const PlaneFit next = fit_plane(Q, subset, extent_sq, params, rng, min_share);
        total_tries += next.tries;
        bool at_angle = next.count >= min_share;
        for (int e = 0; e < plane && at_angle; ++e)
          at_angle = std::abs(next.plane.normal.dot(normals_found[e])) < cos_second_angle;
        if (!at_angle) break;
        normals_found[plane] = next.plane.normal;
        std::size_t kept = 0;
        for (const std::uint32_t t : subset) {
          inlier[t] = next.plane.distance(Q[t]) < params.lambda;
          if (!inlier[t]) subset[kept++] = t;
        }
        subset.resize(kept);
      }
      for (std::uint32_t t = 0; t < k; ++t) {
        const std::uint32_t j = nb[t];
        if (inlier[t]) {
#pragma omp atomic
          ++T[j];
        }
#pragma omp atomic
        ++N[j];
      }
    }
  }
  counter.advance(n);

  out.is_texture.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    // Eq. 2: underlying surface iff T_i > δ·N_i. A point that no plane
    // judged (N_i = 0) is left as underlying surface: nothing marks it texture.
    const bool texture = N[i] > 0 && !(T[i] > params.delta * N[i]);
    out.is_texture[i] = texture;
    out.texture_points += texture;
  }
  out.no_plane = no_plane;
  out.mean_iterations = n ? total_tries / static_cast<double>(n) : 0.0;
  return out;
}

}  // namespace detexture
