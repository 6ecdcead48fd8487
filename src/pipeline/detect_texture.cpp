#include "detexture/pipeline/detect_texture.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

#include "pipeline/random.h"
#include "progress_counter.h"

namespace detexture {
namespace {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;  // plane: normal . q = offset
  double distance(const Eigen::Vector3d& q) const { return std::abs(normal.dot(q) - offset); }
};

std::size_t count_inliers(const std::vector<Eigen::Vector3d>& Q, const Plane& plane,
                          double lambda) {
  std::size_t c = 0;
  for (const auto& q : Q) c += plane.distance(q) < lambda;
  return c;
}

// RANSAC tries needed to draw an all-inlier triple with the given confidence
// when a fraction w of the points are inliers.
double tries_needed(double w, double confidence) {
  const double all_in = w * w * w;
  if (all_in >= 1.0 - 1e-12) return 1.0;
  if (all_in <= 0.0) return 1e18;
  return std::log(1.0 - confidence) / std::log(1.0 - all_in);
}

}  // namespace

void validate(const DetectTextureParams& p) {
  if (!(p.lambda > 0.0) || !std::isfinite(p.lambda))
    throw std::invalid_argument("lambda (RANSAC distance threshold) must be positive, got " +
                                std::to_string(p.lambda));
  if (!(p.delta > 0.0 && p.delta < 1.0))
    throw std::invalid_argument("delta (inlier proportion) must lie in (0, 1), got " +
                                std::to_string(p.delta));
  if (!(p.confidence > 0.0 && p.confidence < 1.0))
    throw std::invalid_argument("the RANSAC confidence must lie in (0, 1), got " +
                                std::to_string(p.confidence));
  if (p.max_iterations < 1)
    throw std::invalid_argument("the RANSAC iteration cap must be at least 1, got " +
                                std::to_string(p.max_iterations));
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

#pragma omp parallel reduction(+ : no_plane, total_tries)
  {
    std::vector<Eigen::Vector3d> Q;  // neighbors, relative to p_i
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
      // A triple whose cross product is this small is collinear for our purposes.
      const double min_cross = 1e-12 * extent_sq;

      SplitMix64 rng(params.seed, i);
      Plane best;
      std::size_t best_count = 0;
      double needed = params.max_iterations;
      int tries = 0;
      while (tries < params.max_iterations && tries < needed) {
        ++tries;
        const std::uint32_t a = rng.below(k);
        std::uint32_t b = rng.below(k - 1);
        b += (b >= a);
        std::uint32_t c = rng.below(k - 2);
        const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
        c += (c >= lo);
        c += (c >= hi);
        const Eigen::Vector3d cross = (Q[b] - Q[a]).cross(Q[c] - Q[a]);
        const double norm = cross.norm();
        if (norm <= min_cross) continue;
        Plane plane;
        plane.normal = cross / norm;
        plane.offset = plane.normal.dot(Q[a]);
        const std::size_t count = count_inliers(Q, plane, params.lambda);
        if (count > best_count) {
          best_count = count;
          best = plane;
          needed = tries_needed(static_cast<double>(count) / k, params.confidence);
        }
      }
      total_tries += tries;
      if (best_count == 0) {
        ++no_plane;
        continue;
      }
      if (params.refine && best_count >= 3) {
        // Least-squares plane through the inliers of the best plane.
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (const auto& q : Q)
          if (best.distance(q) < params.lambda) mean += q;
        mean /= static_cast<double>(best_count);
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (const auto& q : Q)
          if (best.distance(q) < params.lambda)
            cov.noalias() += (q - mean) * (q - mean).transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        Plane refined;
        refined.normal = eig.eigenvectors().col(0);
        refined.offset = refined.normal.dot(mean);
        if (eig.eigenvalues()(1) > 0.0 && count_inliers(Q, refined, params.lambda) >= best_count)
          best = refined;
      }
      for (std::uint32_t t = 0; t < k; ++t) {
        const std::uint32_t j = nb[t];
        if (best.distance(Q[t]) < params.lambda) {
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
