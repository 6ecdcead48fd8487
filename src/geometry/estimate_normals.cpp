#include "detexture/geometry/estimate_normals.h"

#include <Eigen/Eigenvalues>
#include <stdexcept>
#include <string>

#include "progress_counter.h"

namespace detexture {
namespace {

struct PointPca {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // zero if degenerate
  double variation = 0.0;
  bool degenerate = true;
};

// PCA of the neighborhood [begin, end) of point i. Coordinates are taken
// relative to p_i: p_j - p_i is exact for nearby points, so clouds far from
// the origin lose no precision, and identical points give exact zeros.
PointPca pca(const Positions& P, std::size_t i, const std::uint32_t* begin,
             const std::uint32_t* end) {
  PointPca result;
  const std::ptrdiff_t count = end - begin;
  if (count < 3) return result;
  const Eigen::RowVector3d origin = P.row(i);
  Eigen::RowVector3d mean = Eigen::RowVector3d::Zero();
  for (const std::uint32_t* j = begin; j != end; ++j) mean += P.row(*j) - origin;
  mean /= static_cast<double>(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const std::uint32_t* j = begin; j != end; ++j) {
    const Eigen::RowVector3d q = P.row(*j) - origin - mean;
    covariance.noalias() += q.transpose() * q;
  }
  covariance /= static_cast<double>(count);

  // Not computeDirect: see the header for why accuracy wins here.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Eigen::Vector3d lambda = solver.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = lambda.sum();
  if (sum > 0.0) result.variation = lambda(0) / sum;
  if (lambda(1) <= kMinSpreadRatio * kMinSpreadRatio * lambda(2)) return result;
  result.normal = solver.eigenvectors().col(0).normalized();
  result.degenerate = false;
  return result;
}

void check_sizes(const Positions& P, const Neighborhoods& N) {
  if (N.size() != static_cast<std::size_t>(P.rows()))
    throw std::invalid_argument("the neighborhoods were computed for " + std::to_string(N.size()) +
                                " points, but the cloud has " + std::to_string(P.rows()));
}

}  // namespace

EstimateNormalsResult estimate_normals(const Positions& P, const Neighborhoods& N,
                                       const ProgressFn& progress) {
  check_sizes(P, N);
  const std::ptrdiff_t n = P.rows();
  EstimateNormalsResult result;
  result.normals.setZero(n, 3);
  result.variation.setZero(n);
  constexpr std::ptrdiff_t kTick = 4096;
  ProgressCounter counter(progress, static_cast<std::size_t>(n));
  std::size_t degenerate = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : degenerate)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const PointPca p = pca(P, i, N.begin(i), N.end(i));
    result.normals.row(i) = p.normal.transpose();
    result.variation(i) = p.variation;
    if (p.degenerate) ++degenerate;
    if (i % kTick == kTick - 1) counter.advance(kTick);
  }
  counter.advance(static_cast<std::size_t>(n % kTick));
  result.degenerate = degenerate;
  return result;
}

Normals reestimate_zero_normals(const Positions& P, const Normals& normals, const Neighborhoods& N,
                                std::size_t* reestimated) {
  check_sizes(P, N);
  if (normals.rows() != P.rows())
    throw std::invalid_argument("the cloud has " + std::to_string(P.rows()) + " points but " +
                                std::to_string(normals.rows()) + " normals");
  const std::ptrdiff_t n = P.rows();
  Normals result = normals;
  std::size_t replaced = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : replaced)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (normals.row(i).squaredNorm() != 0.0) continue;
    const PointPca p = pca(P, i, N.begin(i), N.end(i));
    if (p.degenerate) continue;
    Eigen::RowVector3d reference = Eigen::RowVector3d::Zero();
    for (const std::uint32_t* j = N.begin(i); j != N.end(i); ++j) reference += normals.row(*j);
    const double agreement = reference.dot(p.normal.transpose());
    if (agreement == 0.0) continue;
    result.row(i) = (agreement > 0.0 ? 1.0 : -1.0) * p.normal.transpose();
    ++replaced;
  }
  if (reestimated) *reestimated = replaced;
  return result;
}

}  // namespace detexture
