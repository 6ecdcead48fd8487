#include "detexture/pipeline/detect_texture.h"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "progress_counter.h"
#include "random.h"

namespace detexture {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The inlier count, RANSAC's inner loop, is also compiled for AVX2 (8 floats
// per instruction instead of SSE2's 4) and chosen when the processor has it.
// Each point's test is the same float operations either way (AVX2 does not
// bring FMA contraction; that is -mfma), so the counts, and the output, are
// the same to the bit on any x86-64 machine.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__linux__)
#define COUNT_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define COUNT_CLONES
#endif

// Neighbors of one point as structure-of-arrays floats relative to the point,
// so that counting a plane's inliers is one contiguous loop the compiler
// vectorizes (4 per instruction with SSE2; with the early exit below, the
// stage went from 0.60 to 0.47 s on bench/speed's 150k sphere, same texture count).
// Float is ample: coordinates are within r of the centre and λ is a few
// percent of r.
struct Points {
  std::vector<float> x, y, z;
  std::vector<float> nx, ny, nz;  // their normals, when the caller gave normals
  std::vector<std::uint32_t> id;  // position in R_i
  std::size_t size() const { return x.size(); }
  void clear() {
    x.clear();
    y.clear();
    z.clear();
    nx.clear();
    ny.clear();
    nz.clear();
    id.clear();
  }
  bool has_normals() const { return nx.size() == x.size() && !x.empty(); }
  // Point t against a model, with its normal where there is one.
  bool fits(const struct SurfaceTest& model, std::size_t t, float lambda, float min_cos) const;
  // k points, with normals or not, to be written in place (cheaper than k
  // push_backs, which were 4% of a run on the real suite's bull).
  void resize(std::size_t k, bool normals) {
    x.resize(k);
    y.resize(k);
    z.resize(k);
    id.resize(k);
    nx.resize(normals ? k : 0);
    ny.resize(normals ? k : 0);
    nz.resize(normals ? k : 0);
  }
};

// A plane in float, for the inlier test: n . q = d.
struct PlaneTest {
  float nx = 0, ny = 0, nz = 0, d = 0;
  // The one inlier test, used for fitting and for the final counts alike.
  bool fits(float px, float py, float pz, float lambda) const {
    return std::abs(nx * px + ny * py + nz * pz - d) < lambda;
  }
  // Normal (qnx, qny, qnz) within acos(min_cos) of the plane's, either sign.
  bool agrees(float qnx, float qny, float qnz, float min_cos) const {
    return min_cos <= -1.0f || std::abs(nx * qnx + ny * qny + nz * qnz) >= min_cos;
  }
};

// The first model of a neighborhood: a plane n . q = d, optionally bent by a
// quadratic height over it, h(u, v) = a u^2 + b u v + c v^2 + e u + f v with
// u = e1 . q, v = e2 . q (e1, e2, n orthonormal). With a = ... = f = 0 it is
// the plane test above, to the bit.
struct SurfaceTest {
  PlaneTest plane;
  float e1x = 0, e1y = 0, e1z = 0, e2x = 0, e2y = 0, e2z = 0;
  float a = 0, b = 0, c = 0, e = 0, f = 0;
  bool curved = false;
  // The pieces of the tests below, each one expression, so that the batch
  // and fused tests (fit_flags, fits_and_agrees) compute them to the bit.
  float height(float px, float py, float pz) const {
    return plane.nx * px + plane.ny * py + plane.nz * pz - plane.d;
  }
  float u_of(float px, float py, float pz) const { return e1x * px + e1y * py + e1z * pz; }
  float v_of(float px, float py, float pz) const { return e2x * px + e2y * py + e2z * pz; }
  bool bent_fits(float h, float u, float v, float lambda) const {
    return std::abs(h - (a * u * u + b * u * v + c * v * v + e * u + f * v)) < lambda;
  }
  // The quadric's (unnormalized) normal at (u, v), dotted with (qnx, qny,
  // qnz): dot and the normal's length.
  void bent_normal_dot(float u, float v, float qnx, float qny, float qnz, float* dot,
                       float* length) const {
    const float gu = 2 * a * u + b * v + e, gv = b * u + 2 * c * v + f;
    const float mx = plane.nx - gu * e1x - gv * e2x, my = plane.ny - gu * e1y - gv * e2y,
                mz = plane.nz - gu * e1z - gv * e2z;
    *dot = mx * qnx + my * qny + mz * qnz;
    *length = std::sqrt(mx * mx + my * my + mz * mz);
  }
  // The plane's normal from RANSAC has either sign.
  static bool within(float dot, float length, float min_cos) {
    return std::abs(dot) >= min_cos * length;
  }
  bool fits(float px, float py, float pz, float lambda) const {
    const float h = height(px, py, pz);
    if (!curved) return std::abs(h) < lambda;
    return bent_fits(h, u_of(px, py, pz), v_of(px, py, pz), lambda);
  }
  // The same, and for a curved model the point's normal (nx, ny, nz) must
  // also lie within acos(min_cos) of the model's normal there (see
  // refine_quadric). min_cos <= -1 skips that test.
  bool fits(float px, float py, float pz, float qnx, float qny, float qnz, float lambda,
            float min_cos) const {
    if (!fits(px, py, pz, lambda)) return false;
    if (!curved || min_cos <= -1.0f) return true;
    return agrees(px, py, pz, qnx, qny, qnz, min_cos);
  }
  // The normal test alone, for the plane or the quadric at (px, py, pz).
  bool agrees(float px, float py, float pz, float qnx, float qny, float qnz, float min_cos) const {
    if (min_cos <= -1.0f) return true;
    if (!curved) return plane.agrees(qnx, qny, qnz, min_cos);
    float dot, length;
    bent_normal_dot(u_of(px, py, pz), v_of(px, py, pz), qnx, qny, qnz, &dot, &length);
    return within(dot, length, min_cos);
  }
  // fits(..., min_cos) && agrees(..., vote_cos), with the quadric's normal
  // computed once (Eq. 2's votes in the gather pass).
  // The tests are combined without branches: whether a neighbor fits is a
  // coin toss on dense relief, and mispredictions cost more than the
  // normal's square root.
  bool fits_and_agrees(float px, float py, float pz, float qnx, float qny, float qnz, float lambda,
                       float min_cos, float vote_cos) const {
    const float h = height(px, py, pz);
    if (!curved) return (std::abs(h) < lambda) & plane.agrees(qnx, qny, qnz, vote_cos);
    const float u = u_of(px, py, pz), v = v_of(px, py, pz);
    const bool fits = bent_fits(h, u, v, lambda);
    if (min_cos <= -1.0f && vote_cos <= -1.0f) return fits;
    float dot, length;
    bent_normal_dot(u, v, qnx, qny, qnz, &dot, &length);
    return fits & (min_cos <= -1.0f || within(dot, length, min_cos)) &
           (vote_cos <= -1.0f || within(dot, length, vote_cos));
  }
};

bool Points::fits(const SurfaceTest& model, std::size_t t, float lambda, float min_cos) const {
  if (!has_normals()) return model.fits(x[t], y[t], z[t], lambda);
  return model.fits(x[t], y[t], z[t], nx[t], ny[t], nz[t], lambda, min_cos);
}

// flags[t] = S.fits(model, t, lambda, min_cos) for every t, in loops without
// branches that the compiler vectorizes (the quadric's tests were 12% of a run
// on the real suite's bull, point by point). Returns the count.
std::size_t fit_flags(const Points& S, const SurfaceTest& model, float lambda, float min_cos,
                      std::vector<std::uint8_t>& flags) {
  const std::size_t k = S.size();
  flags.resize(k);
  std::uint8_t* out = flags.data();
  const float* x = S.x.data();
  const float* y = S.y.data();
  const float* z = S.z.data();
  if (!model.curved) {
    for (std::size_t t = 0; t < k; ++t) out[t] = std::abs(model.height(x[t], y[t], z[t])) < lambda;
  } else if (!S.has_normals() || min_cos <= -1.0f) {
    for (std::size_t t = 0; t < k; ++t)
      out[t] = model.bent_fits(model.height(x[t], y[t], z[t]), model.u_of(x[t], y[t], z[t]),
                               model.v_of(x[t], y[t], z[t]), lambda);
  } else {
    const float* nx = S.nx.data();
    const float* ny = S.ny.data();
    const float* nz = S.nz.data();
    for (std::size_t t = 0; t < k; ++t) {
      const float u = model.u_of(x[t], y[t], z[t]), v = model.v_of(x[t], y[t], z[t]);
      float dot, length;
      model.bent_normal_dot(u, v, nx[t], ny[t], nz[t], &dot, &length);
      out[t] = model.bent_fits(model.height(x[t], y[t], z[t]), u, v, lambda) &
               SurfaceTest::within(dot, length, min_cos);
    }
  }
  std::size_t count = 0;
  for (std::size_t t = 0; t < k; ++t) count += out[t];
  return count;
}

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;  // plane: normal . q = offset
  PlaneTest test;
  void set(const Eigen::Vector3d& n, double o) {
    normal = n;
    offset = o;
    test = {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()),
            static_cast<float>(o)};
  }
  bool fits(float px, float py, float pz, float lambda) const {
    return test.fits(px, py, pz, lambda);
  }
};

// Inliers of `plane` among S. RANSAC only needs to know whether a plane beats
// the best so far: once the count cannot exceed `beat` even if every
// remaining point fits, it stops and returns a count <= beat.
COUNT_CLONES std::size_t count_inliers(const Points& S, const Plane& plane, float lambda,
                                       std::size_t beat) {
  const std::size_t n = S.size();
  const float* x = S.x.data();
  const float* y = S.y.data();
  const float* z = S.z.data();
  const float nx = plane.test.nx, ny = plane.test.ny, nz = plane.test.nz, d = plane.test.d;
  std::size_t count = 0;
  constexpr std::size_t kChunk = 64;
  for (std::size_t lo = 0; lo < n; lo += kChunk) {
    const std::size_t hi = std::min(n, lo + kChunk);
    std::uint32_t c = 0;
    for (std::size_t t = lo; t < hi; ++t)
      c += std::abs(nx * x[t] + ny * y[t] + nz * z[t] - d) < lambda;
    count += c;
    if (count + (n - hi) <= beat) return count;
  }
  return count;
}

// RANSAC tries needed to draw an all-inlier triple with the given confidence
// when a fraction w of the points are inliers.
double tries_needed(double w, double confidence) {
  const double all_in = w * w * w;
  if (all_in >= 1.0 - 1e-12) return 1.0;
  if (all_in <= 0.0) return 1e18;
  return std::log(1.0 - confidence) / std::log(1.0 - all_in);
}

// RANSAC with adaptive termination over S, then an optional least-squares
// refit to the inliers. count is 0 when no non-degenerate triple was found.
struct PlaneFit {
  Plane plane;
  std::size_t count = 0;
  int tries = 0;
};

// The t in [0, k) with fits(t), listed without a branch per point (whether a
// point fits is a coin toss on dense relief, and the mispredicted branches
// cost more than the sums they skipped). Returns how many.
template <class Fits>
std::size_t list_inliers(std::size_t k, Fits fits, std::vector<std::uint32_t>& held) {
  held.resize(k);
  std::uint32_t* out = held.data();
  std::size_t m = 0;
  for (std::size_t t = 0; t < k; ++t) {
    out[m] = static_cast<std::uint32_t>(t);
    m += fits(t);
  }
  return m;
}

// Sums over the inliers (in double; coordinates are within r of the centre,
// so the moments lose nothing that matters), in the order of S.
bool least_squares_plane(const Points& S, const Plane& plane, float lambda, std::size_t count,
                         std::vector<std::uint32_t>& held, Plane* refined) {
  const std::size_t m = list_inliers(
      S.size(), [&](std::size_t t) { return plane.fits(S.x[t], S.y[t], S.z[t], lambda); }, held);
  double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  for (std::size_t s = 0; s < m; ++s) {
    const std::uint32_t t = held[s];
    const double x = S.x[t], y = S.y[t], z = S.z[t];
    sx += x;
    sy += y;
    sz += z;
    sxx += x * x;
    sxy += x * y;
    sxz += x * z;
    syy += y * y;
    syz += y * z;
    szz += z * z;
  }
  const double inv = 1.0 / static_cast<double>(count);
  const Eigen::Vector3d mean(sx * inv, sy * inv, sz * inv);
  Eigen::Matrix3d cov;
  cov << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
  cov = cov * inv - mean * mean.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  refined->set(eig.eigenvectors().col(0), eig.eigenvectors().col(0).dot(mean));
  return eig.eigenvalues()(1) > 0.0;
}

// min_count: a plane with fewer inliers is of no use to the caller, so once
// enough tries have been made to find such a plane at the chosen confidence,
// RANSAC gives up (the further planes of curved texture would otherwise run
// to the cap).
PlaneFit fit_plane(const Points& S, double extent_sq, const DetectTextureParams& params,
                   float lambda, SplitMix64& rng, double min_count,
                   std::vector<std::uint32_t>& held) {
  const std::uint32_t k = static_cast<std::uint32_t>(S.size());
  // A triple whose cross product is this small is collinear for our purposes.
  const double min_cross = 1e-12 * extent_sq;
  auto point = [&](std::uint32_t t) { return Eigen::Vector3d(S.x[t], S.y[t], S.z[t]); };
  PlaneFit fit;
  double needed = std::min<double>(
      params.max_iterations,
      tries_needed(std::min(1.0, min_count / static_cast<double>(k)), params.confidence));
  // The hypotheses are drawn and solved in batches, ahead of their counts:
  // each count ends in a mispredicted exit, which used to leave every
  // hypothesis's square root and divisions waiting in turn (15% of the bull's
  // detection). The generator is then moved on by the draws of the tries
  // actually made, so the draws, the planes and the result are the same.
  // Batches grow 1, 1, 2, 4, 8 (a flat neighborhood needs one try) and never
  // pass the tries still needed.
  constexpr int kBatch = 8;
  std::array<Plane, kBatch> planes;
  std::array<bool, kBatch> solid;
  while (fit.tries < params.max_iterations && fit.tries < needed) {
    const int batch = static_cast<int>(std::min<double>(
        {static_cast<double>(std::clamp(fit.tries, 1, kBatch)),
         static_cast<double>(params.max_iterations - fit.tries), std::ceil(needed - fit.tries)}));
    SplitMix64 ahead = rng;
    for (int h = 0; h < batch; ++h) {
      const std::uint32_t a = ahead.below(k);
      std::uint32_t b = ahead.below(k - 1);
      b += (b >= a);
      std::uint32_t c = ahead.below(k - 2);
      const std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
      c += (c >= lo);
      c += (c >= hi);
      const Eigen::Vector3d qa = point(a);
      const Eigen::Vector3d cross = (point(b) - qa).cross(point(c) - qa);
      const double norm = cross.norm();
      solid[h] = norm > min_cross;
      if (solid[h]) planes[h].set(cross / norm, (cross / norm).dot(qa));
    }
    int used = 0;
    for (; used < batch && fit.tries < params.max_iterations && fit.tries < needed; ++used) {
      ++fit.tries;
      if (!solid[used]) continue;
      const Plane& plane = planes[used];
      const std::size_t count = count_inliers(S, plane, lambda, fit.count);
      if (count > fit.count) {
        fit.count = count;
        fit.plane = plane;
        needed = std::min(needed, tries_needed(static_cast<double>(count) / k, params.confidence));
      }
    }
    rng.skip(3 * static_cast<std::uint64_t>(used));
  }
  if (params.refine && fit.count >= 3) {
    Plane refined;
    if (least_squares_plane(S, fit.plane, lambda, fit.count, held, &refined)) {
      const std::size_t count = count_inliers(S, refined, lambda, fit.count - 1);
      if (count >= fit.count) {
        fit.plane = refined;
        fit.count = count;
      }
    }
  }
  return fit;
}

// Bends the plane of `fit` into a quadratic height field over it, fitted by
// least squares to the current inliers and re-counted, a few times while the
// inlier count grows (an iteratively reweighted fit with 0/1 weights). Starts
// from the plane's inliers, so relief the plane rejected (a bump) does not
// pull the fit; a curved underlying surface, whose sag over R_i exceeds λ,
// is taken in ring by ring. Curvature is capped at 1/r_min (κ = 2|a| on the
// axes): a quadric that bends more tightly than that fits texture, not shape.
// Returns the inlier count of the result (the plane's when nothing helped).
// flags, held: buffers for the inliers of each round, flagged and listed.
std::size_t refine_quadric(const Points& S, const Plane& plane, std::size_t plane_count,
                           float lambda, float min_cos, double max_curvature, int rounds,
                           std::vector<std::uint8_t>& flags, std::vector<std::uint32_t>& held,
                           SurfaceTest* out) {
  SurfaceTest best;
  best.plane = plane.test;
  std::size_t best_count = plane_count;
  const Eigen::Vector3d n = plane.normal;
  const Eigen::Vector3d helper =
      std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = n.cross(helper).normalized(), e2 = n.cross(e1);
  SurfaceTest trial = best;
  trial.e1x = static_cast<float>(e1.x());
  trial.e1y = static_cast<float>(e1.y());
  trial.e1z = static_cast<float>(e1.z());
  trial.e2x = static_cast<float>(e2.x());
  trial.e2y = static_cast<float>(e2.y());
  trial.e2z = static_cast<float>(e2.z());
  const std::size_t k = S.size();
  // Round 0 fits to the plane's inliers (positions only); each later round to
  // the inliers of the previous round's quadric, counted at its end.
  fit_flags(S, best, lambda, -2.0f, flags);
  for (int round = 0; round < rounds; ++round) {
    // Normal equations of h - d = [u^2 uv v^2 u v 1] . x over the inliers,
    // the upper triangle of A summed term by term (as Eigen's rankUpdate
    // does, to the bit, but without its general-size kernel: 4.6% of a run
    // on the real suite's bull), over the inliers listed first (a branch per
    // point was mispredicted on dense relief), each row's products
    // contiguous so that they are summed in pairs of lanes.
    double A[6][6] = {};
    double b[6] = {};
    const std::size_t used = list_inliers(
        k, [&](std::size_t t) { return flags[t] != 0; }, held);
    double scale_sq = 0.0;
    for (std::size_t i = 0; i < used; ++i) {
      const std::uint32_t t = held[i];
      const double u = trial.e1x * S.x[t] + trial.e1y * S.y[t] + trial.e1z * S.z[t];
      const double v = trial.e2x * S.x[t] + trial.e2y * S.y[t] + trial.e2z * S.z[t];
      const double h =
          plane.test.nx * S.x[t] + plane.test.ny * S.y[t] + plane.test.nz * S.z[t] - plane.test.d;
      scale_sq = std::max(scale_sq, u * u + v * v);
      const double m[6] = {u * u, u * v, v * v, u, v, 1.0};
      for (int r = 0; r < 6; ++r)
        for (int c = r; c < 6; ++c) A[r][c] += m[r] * m[c];
      for (int r = 0; r < 6; ++r) b[r] += h * m[r];
    }
    if (used < 12 || !(scale_sq > 0.0)) break;
    Eigen::Matrix<double, 6, 6> full;
    Eigen::Matrix<double, 6, 1> rhs;
    for (int r = 0; r < 6; ++r) {
      rhs(r) = b[r];
      for (int c = r; c < 6; ++c) full(r, c) = full(c, r) = A[r][c];
    }
    // Scale the unknowns so the system is well conditioned at any r.
    const double s = 1.0 / std::sqrt(scale_sq);
    Eigen::Matrix<double, 6, 1> D;
    D << s * s, s * s, s * s, s, s, 1.0;
    const Eigen::Matrix<double, 6, 6> scaled = D.asDiagonal() * full * D.asDiagonal();
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(scaled);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::Matrix<double, 6, 1> x = D.asDiagonal() * ldlt.solve(D.asDiagonal() * rhs);
    if (!x.allFinite()) break;
    // Principal curvatures of the height field at the centre are the
    // eigenvalues of its Hessian [[2a, b], [b, 2c]].
    const double mean = x(0) + x(2), diff = std::sqrt((x(0) - x(2)) * (x(0) - x(2)) + x(1) * x(1));
    if (std::max(std::abs(mean + diff), std::abs(mean - diff)) > max_curvature) break;
    trial.a = static_cast<float>(x(0));
    trial.b = static_cast<float>(x(1));
    trial.c = static_cast<float>(x(2));
    trial.e = static_cast<float>(x(3));
    trial.f = static_cast<float>(x(4));
    trial.plane.d = static_cast<float>(plane.offset + x(5));
    trial.curved = true;
    const std::size_t count = fit_flags(S, trial, lambda, min_cos, flags);
    if (count <= best_count) break;
    best = trial;
    best_count = count;
  }
  *out = best;
  return best_count;
}

}  // namespace

std::vector<float> hard_omega(const std::vector<std::uint8_t>& is_texture) {
  std::vector<float> omega(is_texture.size());
  for (std::size_t i = 0; i < is_texture.size(); ++i) omega[i] = is_texture[i] ? 0.0f : 1.0f;
  return omega;
}

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
  if (!(p.soft_floor >= 0.0 && p.soft_floor < p.delta))
    throw std::invalid_argument("the soft sub-neighborhood floor must lie in [0, delta), got " +
                                number_text(p.soft_floor));
  if (!(p.min_surface_radius >= 0.0) || !std::isfinite(p.min_surface_radius))
    throw std::invalid_argument(
        "the least radius of curvature of the underlying surface must be >= 0, got " +
        number_text(p.min_surface_radius));
  if (!(p.surface_min_gain >= 0.0 && p.surface_min_gain < 1.0))
    throw std::invalid_argument("the quadric's least gain must lie in [0, 1), got " +
                                number_text(p.surface_min_gain));
  if (!(p.surface_normal_angle_deg > 0.0 && p.surface_normal_angle_deg <= 180.0))
    throw std::invalid_argument("the quadric's normal angle must lie in (0, 180] degrees, got " +
                                number_text(p.surface_normal_angle_deg));
  if (!(p.surface_max_plane_share > 0.0 && p.surface_max_plane_share <= 1.0))
    throw std::invalid_argument("the quadric's plane share must lie in (0, 1], got " +
                                number_text(p.surface_max_plane_share));
  if (!(p.vote_normal_angle_deg > 0.0 && p.vote_normal_angle_deg <= 180.0))
    throw std::invalid_argument("the vote normal angle must lie in (0, 180] degrees, got " +
                                number_text(p.vote_normal_angle_deg));
  if (p.surface_rounds < 1)
    throw std::invalid_argument("the quadric surface needs at least 1 fitting round, got " +
                                number_text(p.surface_rounds));
  if (p.max_iterations < 1)
    throw std::invalid_argument("the RANSAC iteration cap must be at least 1, got " +
                                number_text(p.max_iterations));
}

TextureDetection detect_texture(const Positions& P, const Neighborhoods& R,
                                const DetectTextureParams& params, const ProgressFn& progress) {
  return detect_texture(P, Normals(), R, params, progress);
}

TextureDetection detect_texture(const Positions& P, const Normals& point_normals,
                                const Neighborhoods& R, const DetectTextureParams& params,
                                const ProgressFn& progress) {
  validate(params);
  if (point_normals.rows() != 0 && point_normals.rows() != P.rows())
    throw std::invalid_argument("detect_texture: positions and normals differ in size");
  const bool with_normals = point_normals.rows() != 0;
  const Normals* normals = &point_normals;
  const float min_cos =
      static_cast<float>(std::cos(params.surface_normal_angle_deg * M_PI / 180.0));
  const float vote_cos =
      with_normals && params.vote_normal_angle_deg < 180.0
          ? static_cast<float>(std::cos(params.vote_normal_angle_deg * M_PI / 180.0))
          : -2.0f;
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n)
    throw std::invalid_argument("detect_texture: positions and neighborhoods differ in size");
  TextureDetection out;
  out.inliers.assign(n, 0);
  out.height.assign(n, 0.0f);
  // The surface normals are computed in float and kept so (12 bytes per
  // point instead of 24) while the per-point models, this stage's peak
  // memory, are alive; they become doubles, bit for bit, at the end.
  const bool want_normals = params.surface_normals;
  std::vector<float> surface_normal(want_normals ? 3 * n : 0, 0.0f);
  float* height = out.height.data();
  out.members.assign(n, 0);
  std::uint32_t* T = out.inliers.data();
  std::uint32_t* N = out.members.data();
  std::size_t no_plane = 0;
  double total_tries = 0.0;
  ProgressCounter counter(progress, n);
  const double cos_second_angle = std::cos(params.second_plane_angle_deg * M_PI / 180.0);
  const float lambda = static_cast<float>(params.lambda);
  const bool curved = params.surface == UnderlyingSurface::Quadric;
  const double max_plane_share = params.surface_max_plane_share;
  const double min_gain = params.surface_min_gain;
  const double max_curvature =
      params.min_surface_radius > 0.0 ? 1.0 / params.min_surface_radius : kInfinity;
  // T_j and N_j sum over the neighborhoods R_i that contain j. When j ∈ R_i
  // exactly if i ∈ R_j (radius neighborhoods without a cap), they are
  // gathered over R_j afterwards from the planes each point keeps; otherwise
  // each neighborhood adds to its members with atomics, which cost 6% of a
  // whole run. Both give the same counts (tested). Most points keep one
  // plane, so the first is kept per point and the rare further ones (creases,
  // corners) in a short list by point: 21 bytes per point instead of 49, at
  // what is otherwise the method's peak memory.
  const bool gather = R.symmetric;
  std::vector<SurfaceTest> first_plane(gather ? n : 0);
  std::vector<std::uint8_t> kept_count(gather ? n : 0, 0);
  std::vector<std::vector<std::pair<std::uint32_t, PlaneTest>>> further_by_thread(
      gather ? static_cast<std::size_t>(omp_get_max_threads()) : 0);

#pragma omp parallel reduction(+ : no_plane, total_tries)
  {
    Points all, rest;                       // R_i; the points no plane has taken yet
    std::vector<std::uint8_t> inlier;       // per neighbor: fits one of the planes
    std::vector<std::uint8_t> bent_inlier;  // the same for the quadric model
    std::vector<std::uint8_t> round_flags;  // refine_quadric's inliers per round
    std::vector<std::uint32_t> held;        // the inliers of a fit, listed
    auto* further =
        gather ? &further_by_thread[static_cast<std::size_t>(omp_get_thread_num())] : nullptr;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      if ((i & 1023) == 1023) counter.advance(1024);
      const std::uint32_t k = static_cast<std::uint32_t>(R.count(i));
      const std::uint32_t* nb = R.begin(i);
      if (k < 3) {
        ++no_plane;
        continue;
      }
      all.resize(k, with_normals);
      double extent_sq = 0.0;
      for (std::uint32_t t = 0; t < k; ++t) {
        const std::uint32_t j = nb[t];
        const float qx = static_cast<float>(P(j, 0) - P(i, 0));
        const float qy = static_cast<float>(P(j, 1) - P(i, 1));
        const float qz = static_cast<float>(P(j, 2) - P(i, 2));
        all.x[t] = qx;
        all.y[t] = qy;
        all.z[t] = qz;
        all.id[t] = t;
        if (with_normals) {
          all.nx[t] = static_cast<float>((*normals)(j, 0));
          all.ny[t] = static_cast<float>((*normals)(j, 1));
          all.nz[t] = static_cast<float>((*normals)(j, 2));
        }
        extent_sq = std::max<double>(extent_sq, qx * qx + qy * qy + qz * qz);
      }
      SplitMix64 rng(params.seed, i);
      const PlaneFit first = fit_plane(all, extent_sq, params, lambda, rng, 3.0, held);
      total_tries += first.tries;
      if (first.count == 0) {
        ++no_plane;
        continue;
      }
      // The model: the first plane (or the quadric it bends into) and the
      // further planes fitted to its outliers. Both are tried on curved
      // surfaces, and the quadric is kept only when it explains more of R_i:
      // at a crease the planes already explain both faces, and a quadric
      // bending around the crease would only blur which face a point is on.
      const double min_share = params.second_plane_share * k;
      auto explain = [&](const SurfaceTest& surface, std::vector<std::uint8_t>& fit,
                         std::array<PlaneTest, 2>& found) {
        std::size_t total = fit_flags(all, surface, lambda, min_cos, fit);
        // The points left, copied without a branch per point (written
        // always, kept by advancing), as below: one slot past the end is
        // written and dropped.
        rest.resize(k - total + 1, false);
        for (std::uint32_t t = 0, r = 0; t < k; ++t) {
          rest.x[r] = all.x[t];
          rest.y[r] = all.y[t];
          rest.z[r] = all.z[t];
          rest.id[r] = t;
          r += !fit[t];
        }
        rest.resize(k - total, false);
        // Further planes at an angle to every earlier one, each with a real
        // share of the neighborhood, are the other faces of a crease or
        // corner: their points are surface.
        int count = 0;
        Eigen::Vector3d normals_found[3] = {first.plane.normal};
        for (int plane = 1; plane < params.planes; ++plane) {
          if (rest.size() < std::max(3.0, min_share)) break;
          const PlaneFit next = fit_plane(rest, extent_sq, params, lambda, rng, min_share, held);
          total_tries += next.tries;
          bool at_angle = next.count >= min_share;
          for (int e = 0; e < plane && at_angle; ++e)
            at_angle = std::abs(next.plane.normal.dot(normals_found[e])) < cos_second_angle;
          if (!at_angle) break;
          normals_found[plane] = next.plane.normal;
          found[static_cast<std::size_t>(count++)] = next.plane.test;
          std::size_t kept = 0;
          for (std::size_t s = 0; s < rest.size(); ++s) {
            const bool fits = next.plane.fits(rest.x[s], rest.y[s], rest.z[s], lambda);
            fit[rest.id[s]] = fits;
            total += fits;
            rest.x[kept] = rest.x[s];
            rest.y[kept] = rest.y[s];
            rest.z[kept] = rest.z[s];
            rest.id[kept] = rest.id[s];
            kept += !fits;
          }
          rest.x.resize(kept);
          rest.y.resize(kept);
          rest.z.resize(kept);
          rest.id.resize(kept);
        }
        return std::pair<std::size_t, int>(total, count);
      };
      SurfaceTest surface;
      surface.plane = first.plane.test;
      std::array<PlaneTest, 2> further_found;
      auto [explained, further_count] = explain(surface, inlier, further_found);
      if (curved && explained < max_plane_share * k) {
        SurfaceTest bent;
        if (refine_quadric(all, first.plane, first.count, lambda, min_cos, max_curvature,
                           params.surface_rounds, round_flags, held,
                           &bent) > first.count + min_gain * k) {
          std::array<PlaneTest, 2> bent_found;
          const auto [bent_explained, bent_count] = explain(bent, bent_inlier, bent_found);
          if (bent_explained > explained) {
            surface = bent;
            inlier.swap(bent_inlier);
            further_found = bent_found;
            further_count = bent_count;
          }
        }
      }
      {
        // p_i itself sits at q = 0 relative to its own models.
        float h = std::abs(surface.plane.d);
        // The model's normal at q = 0: the plane's, tilted by the quadric's
        // slope there (e, f) when it is bent.
        Eigen::Vector3f normal(surface.plane.nx, surface.plane.ny, surface.plane.nz);
        if (surface.curved)
          normal -= surface.e * Eigen::Vector3f(surface.e1x, surface.e1y, surface.e1z) +
                    surface.f * Eigen::Vector3f(surface.e2x, surface.e2y, surface.e2z);
        for (int e = 0; e < further_count; ++e) {
          const PlaneTest& f = further_found[static_cast<std::size_t>(e)];
          if (std::abs(f.d) < h) {
            h = std::abs(f.d);
            normal = Eigen::Vector3f(f.nx, f.ny, f.nz);
          }
        }
        height[i] = h;
        if (want_normals) {
          normal.normalize();
          // Signed like p_i's normal where that is clearly on one side (the
          // models of a thin plate may hold the other sheet's points, whose
          // normals point the other way); where p_i's normal is within 30°
          // of the model's plane, as at the foot of a hemisphere whose flank
          // turns past 90°, like the normals of the points the models hold.
          float side = 0.0f;
          if (with_normals) {
            side = static_cast<float>(normal.cast<double>().dot(point_normals.row(i).transpose()));
            if (std::abs(side) < 0.5f) {
              float held = 0.0f;
              for (std::uint32_t t = 0; t < k; ++t)
                if (inlier[t])
                  held += normal.x() * all.nx[t] + normal.y() * all.ny[t] + normal.z() * all.nz[t];
              if (held != 0.0f) side = held;
            }
          }
          if (side < 0.0f) normal = -normal;
          for (int c = 0; c < 3; ++c)
            surface_normal[3 * i + static_cast<std::size_t>(c)] = normal[c];
        }
      }
      const int planes_kept = 1 + further_count;
      if (gather) {
        first_plane[i] = surface;
        for (int e = 0; e < further_count; ++e)
          further->emplace_back(static_cast<std::uint32_t>(i),
                                further_found[static_cast<std::size_t>(e)]);
      }
      if (gather) {
        kept_count[i] = static_cast<std::uint8_t>(planes_kept);
        continue;
      }
      if (vote_cos > -1.0f) {
        // Eq. 2's votes with the normal test (vote_normal_angle_deg): the
        // point's normal must agree with the model it fits.
        for (std::uint32_t t = 0; t < k; ++t) {
          if (!inlier[t]) continue;
          const float x = all.x[t], y = all.y[t], z = all.z[t];
          bool agrees = all.fits(surface, t, lambda, min_cos) &&
                        surface.agrees(x, y, z, all.nx[t], all.ny[t], all.nz[t], vote_cos);
          for (int e = 0; e < further_count && !agrees; ++e) {
            const PlaneTest& f = further_found[static_cast<std::size_t>(e)];
            agrees = f.fits(x, y, z, lambda) && f.agrees(all.nx[t], all.ny[t], all.nz[t], vote_cos);
          }
          inlier[t] = agrees;
        }
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
  if (gather) {
    // The further planes in point order (each thread's list is already in
    // order for its points, and a point's planes come from one thread).
    std::vector<std::pair<std::uint32_t, PlaneTest>> further;
    for (auto& list : further_by_thread) {
      further.insert(further.end(), list.begin(), list.end());
      std::vector<std::pair<std::uint32_t, PlaneTest>>().swap(list);
    }
    std::stable_sort(further.begin(), further.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::uint32_t> further_start(n + 1, 0);
    for (const auto& f : further) ++further_start[f.first + 1];
    for (std::size_t i = 0; i < n; ++i) further_start[i + 1] += further_start[i];
      // The same test on the same float coordinates as in the loop above
      // (p_j - p_i, rounded to float), so each pair is judged identically.
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::size_t j = 0; j < n; ++j) {
      std::uint32_t t_j = 0, n_j = 0;
      float nj[3] = {0, 0, 0};
      if (with_normals)
        for (int c = 0; c < 3; ++c) nj[c] = static_cast<float>((*normals)(j, c));
      for (const std::uint32_t* nb = R.begin(j); nb != R.end(j); ++nb) {
        const std::uint32_t i = *nb;
        const int count = kept_count[i];
        if (count == 0) continue;
        ++n_j;
        const float qx = static_cast<float>(P(j, 0) - P(i, 0));
        const float qy = static_cast<float>(P(j, 1) - P(i, 1));
        const float qz = static_cast<float>(P(j, 2) - P(i, 2));
        const SurfaceTest& first = first_plane[i];
        bool fits = with_normals ? first.fits_and_agrees(qx, qy, qz, nj[0], nj[1], nj[2], lambda,
                                                         min_cos, vote_cos)
                                 : first.fits(qx, qy, qz, lambda);
        for (std::uint32_t e = further_start[i]; e < further_start[i + 1] && !fits; ++e)
          fits = further[e].second.fits(qx, qy, qz, lambda) &
                 further[e].second.agrees(nj[0], nj[1], nj[2], vote_cos);
        t_j += fits;
      }
      T[j] = t_j;
      N[j] = n_j;
    }
  }
  counter.advance(n);

  out.is_texture.assign(n, 0);
  out.omega.assign(n, 1.0f);
  const bool soft = params.subneighborhood == SubneighborhoodMode::Soft;
  for (std::size_t i = 0; i < n; ++i) {
    // Eq. 2: underlying surface iff T_i > δ·N_i. A point that no plane
    // judged (N_i = 0) is left as underlying surface: nothing marks it texture.
    const bool texture = N[i] > 0 && !(T[i] > params.delta * N[i]);
    out.is_texture[i] = texture;
    out.texture_points += texture;
    if (N[i] == 0) continue;
    if (soft) {
      const double share = static_cast<double>(T[i]) / N[i];
      out.omega[i] = static_cast<float>(
          std::clamp((share - params.soft_floor) / (params.delta - params.soft_floor), 0.0, 1.0));
    } else {
      out.omega[i] = texture ? 0.0f : 1.0f;
    }
  }
  out.no_plane = no_plane;
  out.mean_iterations = n ? total_tries / static_cast<double>(n) : 0.0;
  if (want_normals) {
    std::vector<SurfaceTest>().swap(first_plane);
    std::vector<std::uint8_t>().swap(kept_count);
    out.surface_normal = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(
                             surface_normal.data(), static_cast<Eigen::Index>(n), 3)
                             .cast<double>();
  }
  return out;
}

}  // namespace detexture
