#include "detexture/eval/synthesize_shape.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "detexture/geometry/point_index.h"
#include "random.h"

namespace detexture {
namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kSphereRadius = 0.5;
constexpr double kCylinderRadius = 0.5;
constexpr double kHalfHeight = 0.5;  // cube half side, cylinder and pyramid half height
constexpr double kTorusMajor = 0.35;
constexpr double kTorusMinor = 0.15;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Random streams: each point draws from its own generator seeded by
// (seed, stream, index), so results do not depend on the thread count. The
// generator and the normal deviates are written out (splitmix64, Box-Muller)
// rather than taken from <random>, whose distributions differ between
// standard libraries.
enum Stream : std::uint64_t { kPoints = 1, kGroundTruth, kFeatures, kSigns };

std::uint64_t mix64(std::uint64_t x) { return splitmix64_mix(x + 0x9E3779B97F4A7C15ull); }

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream, std::uint64_t index)
      : state_(mix64(mix64(mix64(seed) ^ stream) ^ index)) {}
  /// Uniform in [0, 1), 53 random bits.
  double uniform() {
    state_ += 0x9E3779B97F4A7C15ull;
    return static_cast<double>(mix64(state_) >> 11) * 0x1.0p-53;
  }
  double normal() {
    const double u = 1.0 - uniform();  // (0, 1]
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * kPi * uniform());
  }

 private:
  std::uint64_t state_;
};

double random_sign(std::uint64_t seed, std::uint64_t index) {
  return Rng(seed, kSigns, index).uniform() < 0.5 ? -1.0 : 1.0;
}

// The base surface at a point: outward normal n, principal directions t1, t2
// with t1 x t2 = n and curvatures k1, k2 in the convention dn/dt_i = k_i t_i
// (a sphere of radius r has k = 1/r), and the distance e to the nearest
// patch border with its gradient.
struct Frame {
  Vector3d n, t1, t2;
  double k1 = 0.0, k2 = 0.0;
  double edge_distance = kInfinity;
  Vector3d edge_gradient = Vector3d::Zero();
};

// A flat convex polygon, corners counter-clockwise around n.
struct FlatFace {
  Vector3d n, t1, t2;
  std::vector<Vector3d> corners;
  std::vector<double> fan_cdf;  // area CDF of the triangles (c0, c_i, c_i+1)
  double area = 0.0;
};

FlatFace make_face(std::vector<Vector3d> corners) {
  FlatFace f;
  f.corners = std::move(corners);
  f.t1 = (f.corners[1] - f.corners[0]).normalized();
  f.n = (f.corners[1] - f.corners[0]).cross(f.corners[2] - f.corners[0]).normalized();
  f.t2 = f.n.cross(f.t1);
  for (std::size_t i = 1; i + 1 < f.corners.size(); ++i) {
    f.area += 0.5 * (f.corners[i] - f.corners[0]).cross(f.corners[i + 1] - f.corners[0]).norm();
    f.fan_cdf.push_back(f.area);
  }
  for (double& c : f.fan_cdf) c /= f.area;
  return f;
}

// ---------------------------------------------------------------------------
// The one-patch shapes after Plane. Each samples its points uniformly by area
// together with their exact frame, and finds the frame of any point on it.
class SmoothSurface {
 public:
  virtual ~SmoothSurface() = default;
  virtual double area() const = 0;
  virtual double diagonal() const = 0;
  /// A point uniform by area, with its frame.
  virtual Vector3d sample(Rng& rng, Frame& frame) const = 0;
  /// The frame at a point on the surface (within ~1e-9).
  virtual Frame frame(const Vector3d& b) const = 0;
};

Vector3d uniform_direction(Rng& rng) {
  const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vector3d(r * std::cos(phi), r * std::sin(phi), z);
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the three-term
// recurrence of the Legendre polynomials).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = 0.0;
      for (int j = 0; j < n; ++j) {
        const double p2 = p1;
        p1 = p0;
        p0 = ((2.0 * j + 1.0) * z * p1 - j * p2) / (j + 1.0);
      }
      dp = n * (z * p0 - p1) / (z * z - 1.0);
      const double step = p0 / dp;
      z -= step;
      if (std::abs(step) < 1e-15) break;
    }
    x[i] = z;
    w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
  }
}

// Integral over the unit sphere of f(d) dOmega: Gauss-Legendre in the polar
// angle theta (the integrand f sin(theta) is analytic on [0, pi] for smooth
// f) and the trapezoid rule in phi (periodic), both spectrally accurate:
// the blob's and the ellipsoid's areas agree with 384 x 768 nodes to 1e-15.
template <class F>
double sphere_integral(F f, int n_theta = 256, int n_phi = 512) {
  std::vector<double> x, w;
  gauss_legendre(n_theta, x, w);
  double total = 0.0;
  for (int i = 0; i < n_theta; ++i) {
    const double theta = 0.5 * kPi * (x[i] + 1.0), s = std::sin(theta), c = std::cos(theta);
    double ring = 0.0;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * kPi * j / n_phi;
      ring += f(Vector3d(s * std::cos(phi), s * std::sin(phi), c));
    }
    total += w[i] * 0.5 * kPi * s * ring * 2.0 * kPi / n_phi;
  }
  return total;
}

// The frame of the level set F = 0 at x from the gradient of F, given in
// closed form: n = grad F / |grad F|, and the shape operator dn/dt =
// P H t / |grad F| (H the Hessian of F, P the tangent projection) from
// central differences of the gradient, diagonalized in the tangent plane.
template <class Gradient>
Frame implicit_frame(const Vector3d& x, const Gradient& gradient) {
  constexpr double kStep = 1e-6;
  const Vector3d g = gradient(x);
  const double length = g.norm();
  Frame f;
  f.n = g / length;
  const Vector3d e1 = f.n.unitOrthogonal(), e2 = f.n.cross(e1);
  const Vector3d h1 = (gradient(x + kStep * e1) - gradient(x - kStep * e1)) / (2.0 * kStep);
  const Vector3d h2 = (gradient(x + kStep * e2) - gradient(x - kStep * e2)) / (2.0 * kStep);
  const double s11 = e1.dot(h1) / length, s22 = e2.dot(h2) / length;
  const double s12 = 0.5 * (e1.dot(h2) + e2.dot(h1)) / length;
  const double mean = 0.5 * (s11 + s22), radius = std::hypot(0.5 * (s11 - s22), s12);
  const double angle = 0.5 * std::atan2(2.0 * s12, s11 - s22);
  f.k1 = mean + radius;
  f.k2 = mean - radius;
  f.t1 = std::cos(angle) * e1 + std::sin(angle) * e2;
  f.t2 = f.n.cross(f.t1);
  return f;
}

// x^2/a^2 + y^2/b^2 + z^2/c^2 = 1. Points are a∘d for directions d
// uniform on the sphere, kept with probability J(d) / max J, where
// J = abc |d / a| is the area scale of d -> a∘d.
class EllipsoidSurface : public SmoothSurface {
 public:
  EllipsoidSurface() : axes_(0.5, 0.32, 0.2) {
    area_ = sphere_integral([&](const Vector3d& d) { return jacobian(d); });
  }
  double area() const override { return area_; }
  double diagonal() const override { return 2.0 * axes_.norm(); }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    const double bound = axes_.prod() / axes_.minCoeff();
    Vector3d d;
    do d = uniform_direction(rng);
    while (rng.uniform() * bound > jacobian(d));
    const Vector3d b = axes_.cwiseProduct(d);
    frame = this->frame(b);
    return b;
  }
  Frame frame(const Vector3d& b) const override {
    const Vector3d inverse_sq = axes_.cwiseProduct(axes_).cwiseInverse();
    return implicit_frame(
        b, [&](const Vector3d& x) { return Vector3d(2.0 * x.cwiseProduct(inverse_sq)); });
  }

 private:
  double jacobian(const Vector3d& d) const { return axes_.prod() * d.cwiseQuotient(axes_).norm(); }
  Vector3d axes_;
  double area_ = 0.0;
};

// z = c (x^2 - y^2) over the disk rho = |(x, y)| <= 0.5, normal up; the
// border distance is measured in the xy projection, 0.5 - rho.
class SaddleSurface : public SmoothSurface {
 public:
  static constexpr double kC = 0.6, kRadius = 0.5;
  double area() const override {
    const double q = 4.0 * kC * kC;  // |grad z|^2 = q rho^2
    return 2.0 * kPi / (3.0 * q) * (std::pow(1.0 + q * kRadius * kRadius, 1.5) - 1.0);
  }
  double diagonal() const override {
    const double height = 2.0 * kC * kRadius * kRadius;
    return std::sqrt(2.0 * 4.0 * kRadius * kRadius + height * height);
  }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    const double q = 4.0 * kC * kC, bound = std::sqrt(1.0 + q * kRadius * kRadius);
    double x, y;
    do {
      const double rho = kRadius * std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
      x = rho * std::cos(phi);
      y = rho * std::sin(phi);
    } while (rng.uniform() * bound > std::sqrt(1.0 + q * (x * x + y * y)));
    const Vector3d b(x, y, kC * (x * x - y * y));
    frame = this->frame(b);
    return b;
  }
  Frame frame(const Vector3d& b) const override {
    Frame f = implicit_frame(
        b, [](const Vector3d& x) { return Vector3d(-2.0 * kC * x.x(), 2.0 * kC * x.y(), 1.0); });
    const double rho = b.head<2>().norm();
    f.edge_distance = kRadius - rho;
    if (rho > 0.0) f.edge_gradient = -Vector3d(b.x(), b.y(), 0.0) / rho;
    return f;
  }
};

// A tube of radius r around the trefoil c(t) = s (sin t + 2 sin 2t,
// cos t - 2 cos 2t, -1.5 sin 3t). A point is c(t) + r m with m a unit
// vector normal to c'(t); its normal is m, its principal directions the
// tangent T (curvature -(m.K) / (1 - r m.K), K = dT/ds the curvature vector)
// and m's circle (curvature 1/r). The area element is
// |c'(t)| (1 - r m.K) r dt dtheta, so area = 2 pi r L.
class KnotSurface : public SmoothSurface {
 public:
  static constexpr double kTube = 0.07, kScale = 0.43 / 3.0, kLift = 1.5;
  static constexpr int kCurvePoints = 4096;

  KnotSurface() : curve_points_(kCurvePoints, 3) {
    Vector3d low = Vector3d::Constant(kInfinity), high = -low;
    for (int i = 0; i < kCurvePoints; ++i) {
      const double t = 2.0 * kPi * i / kCurvePoints;
      Vector3d c, d1, d2;
      curve(t, c, d1, d2);
      curve_points_.row(i) = c.transpose();
      length_ += d1.norm() * 2.0 * kPi / kCurvePoints;  // trapezoid rule, periodic
      const double speed = d1.norm();
      const Vector3d tangent = d1 / speed;
      const Vector3d K = (d2 - d2.dot(tangent) * tangent) / (speed * speed);
      density_bound_ = std::max(density_bound_, speed * (1.0 + kTube * K.norm()));
      for (int a = 0; a < 3; ++a) {
        const double reach = kTube * std::sqrt(std::max(0.0, 1.0 - tangent[a] * tangent[a]));
        low[a] = std::min(low[a], c[a] - reach);
        high[a] = std::max(high[a], c[a] + reach);
      }
    }
    density_bound_ *= 1.01;  // the grid maximum, with a margin for the maximum between nodes
    diagonal_ = (high - low).norm();
    index_ = std::make_unique<PointIndex>(curve_points_);
  }
  double area() const override { return 2.0 * kPi * kTube * length_; }
  double diagonal() const override { return diagonal_; }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    for (;;) {
      const double t = 2.0 * kPi * rng.uniform(), theta = 2.0 * kPi * rng.uniform();
      Vector3d c, d1, d2;
      curve(t, c, d1, d2);
      const Vector3d tangent = d1.normalized(), u = tangent.unitOrthogonal(), v = tangent.cross(u);
      const Vector3d m = std::cos(theta) * u + std::sin(theta) * v;
      const double speed = d1.norm();
      const Vector3d K = (d2 - d2.dot(tangent) * tangent) / (speed * speed);
      if (rng.uniform() * density_bound_ > speed * (1.0 - kTube * m.dot(K))) continue;
      // The frame from the point, as evaluate_texture finds it, so that both agree exactly.
      const Vector3d b = c + kTube * m;
      frame = this->frame(b);
      return b;
    }
  }
  Frame frame(const Vector3d& b) const override {
    double distance_sq;
    double t = 2.0 * kPi * index_->nearest(b.data(), &distance_sq) / kCurvePoints;
    Vector3d c, d1, d2;
    // Newton on (c(t) - b).c'(t) = 0, the foot of b on the curve.
    for (int iteration = 0; iteration < 20; ++iteration) {
      curve(t, c, d1, d2);
      const double step = (c - b).dot(d1) / (d1.squaredNorm() + (c - b).dot(d2));
      t -= step;
      if (std::abs(step) < 1e-15) break;
    }
    curve(t, c, d1, d2);
    return tube_frame(d1, d2, (b - c).normalized());
  }
  /// c(t) and its first two derivatives.
  static void curve(double t, Vector3d& c, Vector3d& d1, Vector3d& d2) {
    const double s1 = std::sin(t), c1 = std::cos(t), s2 = std::sin(2 * t), c2 = std::cos(2 * t);
    const double s3 = std::sin(3 * t), c3 = std::cos(3 * t);
    c = kScale * Vector3d(s1 + 2 * s2, c1 - 2 * c2, -kLift * s3);
    d1 = kScale * Vector3d(c1 + 4 * c2, -s1 + 4 * s2, -3 * kLift * c3);
    d2 = kScale * Vector3d(-s1 - 8 * s2, -c1 + 8 * c2, 9 * kLift * s3);
  }

 private:
  static Frame tube_frame(const Vector3d& d1, const Vector3d& d2, const Vector3d& m) {
    const double speed = d1.norm();
    const Vector3d tangent = d1 / speed;
    const Vector3d K = (d2 - d2.dot(tangent) * tangent) / (speed * speed);
    const double mk = m.dot(K);
    Frame f;
    f.n = m;
    f.t1 = tangent;
    f.t2 = m.cross(tangent);
    f.k1 = -mk / (1.0 - kTube * mk);
    f.k2 = 1.0 / kTube;
    return f;
  }
  Positions curve_points_;
  std::unique_ptr<PointIndex> index_;
  double length_ = 0.0, density_bound_ = 0.0, diagonal_ = 0.0;
};

// A star-shaped body r(d) d over unit directions d, r(d) = r0 +
// sum_k L_k exp((d.a_k - 1) / w_k). F(x) = |x| - r(x/|x|) = 0 gives the
// frame; the area scale of d -> r(d) d is J = r sqrt(r^2 + |grad_S r|^2).
class BlobSurface : public SmoothSurface {
 public:
  struct Limb {
    Vector3d axis;
    double length, width;
  };
  static constexpr double kBody = 0.22;
  static std::vector<Limb> limbs() {
    return {{Vector3d(1.0, 0.1, 0.15).normalized(), 0.25, 0.05},
            {Vector3d(-0.45, 0.85, 0.2).normalized(), 0.2, 0.04},
            {Vector3d(-0.5, -0.8, 0.1).normalized(), 0.22, 0.05},
            {Vector3d(0.3, -0.6, -0.7).normalized(), 0.15, 0.06},
            {Vector3d(-0.1, 0.25, 0.95).normalized(), 0.12, 0.1},
            {Vector3d(0.35, 0.7, -0.6).normalized(), 0.1, 0.08}};
  }

  // The bounds, the area and the diagonal take a few sphere quadratures
  // (0.4 s; the blob has no parameters), so they are computed once per
  // process and shared by every BlobSurface.
  BlobSurface() : limbs_(limbs()) {
    static const std::array<double, 3> shared = [this] {
      measure();
      return std::array<double, 3>{jacobian_bound_, area_, diagonal_};
    }();
    jacobian_bound_ = shared[0];
    area_ = shared[1];
    diagonal_ = shared[2];
  }
  double area() const override { return area_; }
  double diagonal() const override { return diagonal_; }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    Vector3d d;
    do d = uniform_direction(rng);
    while (rng.uniform() * jacobian_bound_ > jacobian(d));
    const Vector3d b = radius(d) * d;
    frame = this->frame(b);
    return b;
  }
  Frame frame(const Vector3d& b) const override {
    return implicit_frame(b, [&](const Vector3d& x) {
      const double rho = x.norm();
      const Vector3d d = x / rho;
      return Vector3d(d - radius_gradient(d) / rho);
    });
  }

 private:
  void measure() {
    double radius_bound = kBody, slope_bound = 0.0;
    for (const Limb& l : limbs_) {
      radius_bound += l.length;
      // max over the angle of |grad_S| of one limb: L/w exp(-(1 - cos a)/w) sin a.
      double m = 0.0;
      for (int i = 0; i <= 20000; ++i) {
        const double a = kPi * i / 20000;
        m = std::max(m, std::exp(-(1.0 - std::cos(a)) / l.width) * std::sin(a));
      }
      slope_bound += 1.01 * l.length / l.width * m;
    }
    jacobian_bound_ = radius_bound * std::hypot(radius_bound, slope_bound);
    area_ = sphere_integral([&](const Vector3d& d) { return jacobian(d); });
    // Bounding box: the extreme quadrature node along each of +-x, +-y, +-z,
    // refined by pattern search on the sphere down to steps of 1e-12.
    Vector3d extent[2];
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        const Vector3d axis = (side ? -1.0 : 1.0) * Vector3d::Unit(a);
        auto height = [&](const Vector3d& d) { return radius(d) * d.dot(axis); };
        Vector3d best = axis;
        sphere_integral([&](const Vector3d& d) {
          if (height(d) > height(best)) best = d;
          return 0.0;
        });
        for (double step = 1e-2; step > 1e-12;) {
          const Vector3d u = best.unitOrthogonal(), v = best.cross(u);
          bool moved = false;
          for (const Vector3d& e : {u, Vector3d(-u), v, Vector3d(-v)}) {
            const Vector3d d = (best + step * e).normalized();
            if (height(d) > height(best)) best = d, moved = true;
          }
          if (!moved) step *= 0.5;
        }
        extent[side][a] = height(best);
      }
    diagonal_ = (extent[0] + extent[1]).norm();
  }
  double radius(const Vector3d& d) const {
    double r = kBody;
    for (const Limb& l : limbs_) r += l.length * std::exp((d.dot(l.axis) - 1.0) / l.width);
    return r;
  }
  // The gradient of r on the sphere (tangent to it at d).
  Vector3d radius_gradient(const Vector3d& d) const {
    Vector3d g = Vector3d::Zero();
    for (const Limb& l : limbs_) {
      const double c = d.dot(l.axis);
      g += l.length / l.width * std::exp((c - 1.0) / l.width) * (l.axis - c * d);
    }
    return g;
  }
  double jacobian(const Vector3d& d) const {
    const double r = radius(d);
    return r * std::sqrt(r * r + radius_gradient(d).squaredNorm());
  }
  std::vector<Limb> limbs_;
  double area_ = 0.0, diagonal_ = 0.0, jacobian_bound_ = 0.0;
};

// Two flat sheets z = +-r (r = 0.03) over rho <= R0 = 0.37 joined by the
// outer half of the torus of major radius R0 and tube radius r: outer radius
// 0.4, thickness 0.06, C1 (tangent planes agree where the pieces meet).
class DiscSurface : public SmoothSurface {
 public:
  static constexpr double kHalf = 0.03, kInner = 0.37;
  double area() const override { return 2.0 * sheet_area() + rim_area(); }
  double diagonal() const override {
    const double w = 2.0 * (kInner + kHalf);
    return std::sqrt(2.0 * w * w + 4.0 * kHalf * kHalf);
  }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    const double pick = rng.uniform() * area();
    Vector3d b;
    if (pick < 2.0 * sheet_area()) {
      const double rho = kInner * std::sqrt(rng.uniform()), phi = 2.0 * kPi * rng.uniform();
      b = Vector3d(rho * std::cos(phi), rho * std::sin(phi), pick < sheet_area() ? kHalf : -kHalf);
    } else {
      const double phi = 2.0 * kPi * rng.uniform();
      double psi;  // the angle around the tube, 0 at the outer equator
      do psi = kPi * (rng.uniform() - 0.5);
      while (rng.uniform() * (kInner + kHalf) > kInner + kHalf * std::cos(psi));
      const double rho = kInner + kHalf * std::cos(psi);
      b = Vector3d(rho * std::cos(phi), rho * std::sin(phi), kHalf * std::sin(psi));
    }
    frame = this->frame(b);
    return b;
  }
  Frame frame(const Vector3d& b) const override {
    Frame f;
    const double rho = b.head<2>().norm();
    if (rho <= kInner) {
      const bool top = b.z() > 0.0;
      f.n = Vector3d(0.0, 0.0, top ? 1.0 : -1.0);
      f.t1 = top ? Vector3d(1.0, 0.0, 0.0) : Vector3d(0.0, 1.0, 0.0);
      f.t2 = f.n.cross(f.t1);
      return f;
    }
    const Vector3d radial(b.x() / rho, b.y() / rho, 0.0);
    f.n = (b - kInner * radial).normalized();
    f.t1 = Vector3d(-radial.y(), radial.x(), 0.0);
    f.t2 = f.n.cross(f.t1);
    const double cos_psi = f.n.dot(radial);
    f.k1 = cos_psi / (kInner + kHalf * cos_psi);
    f.k2 = 1.0 / kHalf;
    return f;
  }

 private:
  static double sheet_area() { return kPi * kInner * kInner; }
  static double rim_area() { return 2.0 * kPi * kHalf * (kPi * kInner + 2.0 * kHalf); }
};

// Closest point to p on the triangle (a, b, c) (Ericson, Real-Time Collision
// Detection, 5.1.5).
Vector3d closest_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                             const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

Vector3d closest_on_segment(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double t = length_sq > 0.0 ? std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// A triangle mesh: face normals, k1 = k2 = 0, the distance to the nearest
// boundary edge (an edge of one triangle) as border distance. A point is
// located on the triangle nearest to it: every triangle within distance D of
// p has its centroid within D + (largest centroid-to-corner distance).
class MeshSurface : public SmoothSurface {
 public:
  explicit MeshSurface(const BaseMesh& mesh) : vertices_(mesh.vertices) {
    std::map<std::pair<int, int>, int> edge_uses;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
      const Eigen::Vector3i v = mesh.triangles.row(t).transpose().cast<int>();
      const Vector3d a = vertices_.row(v[0]), b = vertices_.row(v[1]), c = vertices_.row(v[2]);
      const Vector3d cross = (b - a).cross(c - a);
      const double longest_sq =
          std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      if (!(cross.norm() > 1e-12 * longest_sq)) {
        ++degenerate_;
        continue;
      }
      triangles_.push_back(v);
      area_ += 0.5 * cross.norm();
      cdf_.push_back(area_);
      for (int e = 0; e < 3; ++e) {
        const int i = v[e], j = v[(e + 1) % 3];
        ++edge_uses[{std::min(i, j), std::max(i, j)}];
      }
    }
    if (triangles_.empty())
      throw std::invalid_argument("the base mesh has no triangle of non-zero area");
    for (double& c : cdf_) c /= area_;
    centroids_.resize(static_cast<Eigen::Index>(triangles_.size()), 3);
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const Vector3d centroid = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
      centroids_.row(static_cast<Eigen::Index>(t)) = centroid.transpose();
      for (int k = 0; k < 3; ++k) reach_ = std::max(reach_, (corner(t, k) - centroid).norm());
    }
    centroid_index_ = std::make_unique<PointIndex>(centroids_);
    for (const auto& [edge, uses] : edge_uses)
      if (uses == 1) boundary_.push_back(edge);
    midpoints_.resize(static_cast<Eigen::Index>(boundary_.size()), 3);
    for (std::size_t e = 0; e < boundary_.size(); ++e) {
      const Vector3d a = vertices_.row(boundary_[e].first), b = vertices_.row(boundary_[e].second);
      midpoints_.row(static_cast<Eigen::Index>(e)) = (0.5 * (a + b)).transpose();
      half_edge_ = std::max(half_edge_, 0.5 * (b - a).norm());
    }
    if (!boundary_.empty()) midpoint_index_ = std::make_unique<PointIndex>(midpoints_);
    diagonal_ = bounding_box_diagonal(vertices_);
  }
  std::size_t degenerate() const { return degenerate_; }
  double area() const override { return area_; }
  double diagonal() const override { return diagonal_; }
  Vector3d sample(Rng& rng, Frame& frame) const override {
    const std::size_t t = std::min<std::size_t>(
        std::upper_bound(cdf_.begin(), cdf_.end(), rng.uniform()) - cdf_.begin(),
        triangles_.size() - 1);
    const double s = std::sqrt(rng.uniform()), w = rng.uniform();
    const Vector3d b =
        (1.0 - s) * corner(t, 0) + s * (1.0 - w) * corner(t, 1) + s * w * corner(t, 2);
    frame = triangle_frame(t, b);
    return b;
  }
  Frame frame(const Vector3d& b) const override {
    double distance_sq;
    const std::size_t first = centroid_index_->nearest(b.data(), &distance_sq);
    std::size_t best = first;
    double best_distance = (closest(first, b) - b).norm();
    std::vector<std::pair<std::uint32_t, double>> found;
    centroid_index_->within(b.data(), best_distance + reach_ + 1e-12, found);
    for (const auto& candidate : found) {
      const double d = (closest(candidate.first, b) - b).norm();
      if (d < best_distance || (d == best_distance && candidate.first < best))
        best_distance = d, best = candidate.first;
    }
    return triangle_frame(best, b);
  }

 private:
  Vector3d corner(std::size_t t, int k) const {
    return vertices_.row(triangles_[t][k]).transpose();
  }
  Vector3d closest(std::size_t t, const Vector3d& p) const {
    return closest_on_triangle(p, corner(t, 0), corner(t, 1), corner(t, 2));
  }
  Frame triangle_frame(std::size_t t, const Vector3d& b) const {
    Frame f;
    const Vector3d a = corner(t, 0);
    f.n = (corner(t, 1) - a).cross(corner(t, 2) - a).normalized();
    f.t1 = (corner(t, 1) - a).normalized();
    f.t2 = f.n.cross(f.t1);
    if (!midpoint_index_) return f;
    double distance_sq;
    const std::size_t first = midpoint_index_->nearest(b.data(), &distance_sq);
    Vector3d nearest = boundary_point(first, b);
    std::vector<std::pair<std::uint32_t, double>> found;
    midpoint_index_->within(b.data(), (nearest - b).norm() + half_edge_ + 1e-12, found);
    for (const auto& candidate : found) {
      const Vector3d q = boundary_point(candidate.first, b);
      if ((q - b).squaredNorm() < (nearest - b).squaredNorm()) nearest = q;
    }
    f.edge_distance = (b - nearest).norm();
    if (f.edge_distance > 0.0) f.edge_gradient = (b - nearest) / f.edge_distance;
    return f;
  }
  Vector3d boundary_point(std::size_t e, const Vector3d& p) const {
    return closest_on_segment(p, vertices_.row(boundary_[e].first).transpose(),
                              vertices_.row(boundary_[e].second).transpose());
  }
  Positions vertices_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<double> cdf_;
  Positions centroids_, midpoints_;
  std::unique_ptr<PointIndex> centroid_index_, midpoint_index_;
  std::vector<std::pair<int, int>> boundary_;
  double area_ = 0.0, diagonal_ = 0.0, reach_ = 0.0, half_edge_ = 0.0;
  std::size_t degenerate_ = 0;
};

std::unique_ptr<SmoothSurface> make_smooth_surface(const SynthParams& params) {
  switch (params.shape) {
    case BaseShape::Ellipsoid:
      return std::make_unique<EllipsoidSurface>();
    case BaseShape::Saddle:
      return std::make_unique<SaddleSurface>();
    case BaseShape::Knot:
      return std::make_unique<KnotSurface>();
    case BaseShape::Blob:
      return std::make_unique<BlobSurface>();
    case BaseShape::Disc:
      return std::make_unique<DiscSurface>();
    case BaseShape::Mesh:
      return std::make_unique<MeshSurface>(*params.mesh);
    default:
      return nullptr;
  }
}

class BaseSurface {
 public:
  explicit BaseSurface(const SynthParams& params)
      : shape_(params.shape), smooth_(make_smooth_surface(params)) {
    const double h = kHalfHeight;
    switch (shape_) {
      case BaseShape::Cube:
        for (int a = 0; a < 3; ++a)
          for (double s : {1.0, -1.0}) {
            const Vector3d n = s * Vector3d::Unit(a), t1 = Vector3d::Unit((a + 1) % 3);
            const Vector3d t2 = n.cross(t1), c = h * n;
            faces_.push_back(make_face({c - h * t1 - h * t2, c + h * t1 - h * t2,
                                        c + h * t1 + h * t2, c - h * t1 + h * t2}));
          }
        break;
      case BaseShape::Pyramid: {
        const std::array<Vector3d, 4> base = {Vector3d(-h, -h, -h), Vector3d(h, -h, -h),
                                              Vector3d(h, h, -h), Vector3d(-h, h, -h)};
        faces_.push_back(make_face({base[0], base[3], base[2], base[1]}));
        for (int i = 0; i < 4; ++i)
          faces_.push_back(make_face({base[i], base[(i + 1) % 4], Vector3d(0, 0, h)}));
        break;
      }
      case BaseShape::Plane:
        faces_.push_back(make_face(
            {Vector3d(-h, -h, 0), Vector3d(h, -h, 0), Vector3d(h, h, 0), Vector3d(-h, h, 0)}));
        break;
      default:
        break;
    }
    for (int p = 0; p < patch_count(); ++p)
      cdf_.push_back((cdf_.empty() ? 0.0 : cdf_.back()) + area(p));
    for (double& c : cdf_) c /= cdf_.back();
  }

  /// The shapes after Plane: one patch, features kept to their side (header).
  bool normal_aware() const { return smooth_ != nullptr; }
  std::size_t degenerate_triangles() const {
    return shape_ == BaseShape::Mesh ? static_cast<const MeshSurface&>(*smooth_).degenerate() : 0;
  }
  double total_area() const {
    double total = 0.0;
    for (int p = 0; p < patch_count(); ++p) total += area(p);
    return total;
  }

  int patch_count() const {
    if (smooth_) return 1;
    if (!faces_.empty()) return static_cast<int>(faces_.size());
    return shape_ == BaseShape::Cylinder ? 3 : 1;  // cylinder: side, top cap, bottom cap
  }

  double area(int patch) const {
    if (smooth_) return smooth_->area();
    switch (shape_) {
      case BaseShape::Sphere:
        return 4.0 * kPi * kSphereRadius * kSphereRadius;
      case BaseShape::Torus:
        return 4.0 * kPi * kPi * kTorusMajor * kTorusMinor;
      case BaseShape::Cylinder:
        return patch == 0 ? 2.0 * kPi * kCylinderRadius * 2.0 * kHalfHeight
                          : kPi * kCylinderRadius * kCylinderRadius;
      default:
        return faces_[patch].area;
    }
  }

  double diagonal() const {
    if (smooth_) return smooth_->diagonal();
    if (shape_ == BaseShape::Torus) {
      const double w = 2.0 * (kTorusMajor + kTorusMinor), t = 2.0 * kTorusMinor;
      return std::sqrt(2.0 * w * w + t * t);
    }
    return shape_ == BaseShape::Plane ? std::sqrt(2.0) : std::sqrt(3.0);
  }

  int choose_patch(double u) const {
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    return std::min(static_cast<int>(it - cdf_.begin()), patch_count() - 1);
  }

  /// A point uniformly distributed by area on the patch, with its frame.
  Vector3d sample(int patch, Rng& rng, Frame& frame) const {
    if (smooth_) return smooth_->sample(rng, frame);
    const Vector3d b = sample_patch(patch, rng);
    frame = this->frame(patch, b);
    return b;
  }

 private:
  Vector3d sample_patch(int patch, Rng& rng) const {
    switch (shape_) {
      case BaseShape::Sphere: {
        const double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * kPi * rng.uniform();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        return kSphereRadius * Vector3d(r * std::cos(phi), r * std::sin(phi), z);
      }
      case BaseShape::Torus: {
        const double theta = 2.0 * kPi * rng.uniform();
        double phi = 0.0;
        // The area element is proportional to R + r cos(phi): rejection.
        do phi = 2.0 * kPi * rng.uniform();
        while (rng.uniform() * (kTorusMajor + kTorusMinor) >
               kTorusMajor + kTorusMinor * std::cos(phi));
        const double rho = kTorusMajor + kTorusMinor * std::cos(phi);
        return Vector3d(rho * std::cos(theta), rho * std::sin(theta), kTorusMinor * std::sin(phi));
      }
      case BaseShape::Cylinder: {
        const double theta = 2.0 * kPi * rng.uniform(), v = rng.uniform();
        if (patch == 0)
          return Vector3d(kCylinderRadius * std::cos(theta), kCylinderRadius * std::sin(theta),
                          (2.0 * v - 1.0) * kHalfHeight);
        const double rho = kCylinderRadius * std::sqrt(v);
        return Vector3d(rho * std::cos(theta), rho * std::sin(theta),
                        patch == 1 ? kHalfHeight : -kHalfHeight);
      }
      default: {
        const FlatFace& f = faces_[patch];
        const double pick = rng.uniform();
        const std::size_t t = std::min<std::size_t>(
            std::upper_bound(f.fan_cdf.begin(), f.fan_cdf.end(), pick) - f.fan_cdf.begin(),
            f.fan_cdf.size() - 1);
        const double s = std::sqrt(rng.uniform()), w = rng.uniform();
        return (1.0 - s) * f.corners[0] + s * (1.0 - w) * f.corners[t + 1] +
               s * w * f.corners[t + 2];
      }
    }
  }

 public:
  /// The patch a point of the base surface lies on (ties on an edge, where
  /// h = 0, go to either side).
  int patch_of(const Vector3d& b) const {
    if (smooth_) return 0;
    switch (shape_) {
      case BaseShape::Cylinder: {
        const double side = std::abs(b.head<2>().norm() - kCylinderRadius);
        const double cap = std::abs(std::abs(b.z()) - kHalfHeight);
        return side <= cap ? 0 : (b.z() > 0.0 ? 1 : 2);
      }
      case BaseShape::Cube: {
        int a = 0;
        b.cwiseAbs().maxCoeff(&a);
        return 2 * a + (b[a] < 0.0 ? 1 : 0);
      }
      case BaseShape::Pyramid: {
        int best = 0;
        double best_distance = kInfinity;
        for (int p = 0; p < patch_count(); ++p) {
          const double d = std::abs((b - faces_[p].corners[0]).dot(faces_[p].n));
          if (d < best_distance) best_distance = d, best = p;
        }
        return best;
      }
      default:
        return 0;
    }
  }

  Frame frame(int patch, const Vector3d& b) const {
    if (smooth_) return smooth_->frame(b);
    Frame f;
    switch (shape_) {
      case BaseShape::Sphere: {
        f.n = b.normalized();
        const Vector3d helper = std::abs(f.n.z()) < 0.9 ? Vector3d(0, 0, 1) : Vector3d(1, 0, 0);
        f.t1 = helper.cross(f.n).normalized();
        f.t2 = f.n.cross(f.t1);
        f.k1 = f.k2 = 1.0 / kSphereRadius;
        return f;
      }
      case BaseShape::Torus: {
        const Vector3d radial = Vector3d(b.x(), b.y(), 0.0).normalized();
        f.n = (b - kTorusMajor * radial).normalized();
        f.t1 = Vector3d(-radial.y(), radial.x(), 0.0);
        f.t2 = f.n.cross(f.t1);
        const double cos_phi = f.n.dot(radial);
        f.k1 = cos_phi / (kTorusMajor + kTorusMinor * cos_phi);
        f.k2 = 1.0 / kTorusMinor;
        return f;
      }
      case BaseShape::Cylinder: {
        const Vector3d radial = Vector3d(b.x(), b.y(), 0.0);
        const double rho = radial.norm();
        if (patch == 0) {
          f.n = radial / rho;
          f.t1 = Vector3d(-f.n.y(), f.n.x(), 0.0);
          f.t2 = Vector3d::UnitZ();
          f.k1 = 1.0 / kCylinderRadius;
          f.edge_distance = kHalfHeight - std::abs(b.z());
          f.edge_gradient = Vector3d(0, 0, b.z() > 0.0 ? -1.0 : 1.0);
        } else {
          f.n = Vector3d(0.0, 0.0, patch == 1 ? 1.0 : -1.0);
          f.t1 = patch == 1 ? Vector3d(1.0, 0.0, 0.0) : Vector3d(0.0, 1.0, 0.0);
          f.t2 = f.n.cross(f.t1);
          f.edge_distance = kCylinderRadius - rho;
          if (rho > 0.0) f.edge_gradient = -radial / rho;
        }
        return f;
      }
      default: {
        const FlatFace& face = faces_[patch];
        f.n = face.n;
        f.t1 = face.t1;
        f.t2 = face.t2;
        const std::size_t m = face.corners.size();
        for (std::size_t i = 0; i < m; ++i) {
          const Vector3d inward =
              face.n.cross(face.corners[(i + 1) % m] - face.corners[i]).normalized();
          const double d = (b - face.corners[i]).dot(inward);
          if (d < f.edge_distance) f.edge_distance = d, f.edge_gradient = inward;
        }
        return f;
      }
    }
  }

 private:
  BaseShape shape_;
  std::unique_ptr<SmoothSurface> smooth_;
  std::vector<FlatFace> faces_;
  std::vector<double> cdf_;
};

// The feature centers of one patch with their index (which references the
// matrix, so a PatchCenters never moves once built).
struct PatchCenters {
  Positions centers;
  Normals normals;  // base normals at the centers
  std::vector<double> signs;
  std::unique_ptr<PointIndex> tree;
};

// Features of one radius and amplitude, placed by dart throwing.
struct CenterSet {
  double radius = 0.0;     // R of the profile
  double amplitude = 0.0;  // A
  std::vector<std::unique_ptr<PatchCenters>> patches;
};

// Dart throwing on one patch: candidates uniform by area, accepted when at
// least `spacing` from every accepted center (a hash grid of cell `spacing`
// finds them) and at least `margin` from the patch border; stops after
// kMaxFailures consecutive rejections, which leaves the patch nearly
// saturated. Sequential, so it depends on the seed only. On normal-aware
// shapes two centers with nearly opposite normals, n_i.n_j <= -7/8, do not
// conflict: they lie on two sides of a thin part. A point b then takes both
// only where q_i + q_j <= |n_i + n_j| <= 1/2 (q = n(b).n_c), and the side
// weights (smoothsteps with w(q) + w(1/2 - q) = 1) add up to at most 1, so
// |h| <= A still holds. A third center cannot be nearly opposite to both, so
// it keeps the spacing from them.
constexpr double kOppositeSides = -0.875;
std::vector<Vector3d> throw_darts(const BaseSurface& base, int patch, double spacing, double margin,
                                  Rng& rng, std::vector<Vector3d>& normals) {
  constexpr int kMaxFailures = 3000;
  auto cell_of = [&](const Vector3d& x) {
    return Eigen::Vector3i((x / spacing).array().floor().cast<int>());
  };
  auto key_of = [](const Eigen::Vector3i& c) {
    return mix64((static_cast<std::uint64_t>(c.x()) * 73856093u) ^
                 (static_cast<std::uint64_t>(c.y()) * 19349663u) ^
                 (static_cast<std::uint64_t>(c.z()) * 83492791u));
  };
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  std::vector<Vector3d> accepted;
  normals.clear();
  const double spacing_sq = spacing * spacing;
  const bool normal_aware = base.normal_aware();
  for (int failures = 0; failures < kMaxFailures;) {
    Frame frame;
    const Vector3d x = base.sample(patch, rng, frame);
    bool ok = frame.edge_distance >= margin;
    const Eigen::Vector3i c = cell_of(x);
    for (int dx = -1; ok && dx <= 1; ++dx)
      for (int dy = -1; ok && dy <= 1; ++dy)
        for (int dz = -1; ok && dz <= 1; ++dz) {
          const auto it = grid.find(key_of(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if ((accepted[j] - x).squaredNorm() < spacing_sq &&
                (!normal_aware || normals[j].dot(frame.n) > kOppositeSides))
              ok = false;
        }
    if (!ok) {
      ++failures;
      continue;
    }
    failures = 0;
    grid[key_of(c)].push_back(static_cast<int>(accepted.size()));
    accepted.push_back(x);
    normals.push_back(frame.n);
  }
  return accepted;
}

// The height field h on the base surface, as a function of the 3D point b
// on a given patch, with its gradient in R^3 (whose projection on the
// tangent plane is the surface gradient).
class HeightField {
 public:
  HeightField(const SynthParams& params, const BaseSurface& base)
      : params_(params),
        direction_(Vector3d(1.0, 2.0, 3.0).normalized()),
        normal_aware_(base.normal_aware()) {
    const double R = params.size, A = params.amplitude;
    const bool dense = params.layout == TextureLayout::Dense;
    switch (params.texture) {
      case TextureKind::Bumps:
      case TextureKind::Domes:
        add_centers(base, R, A, (dense ? 2.0 : 3.0) * R, R + R);
        break;
      case TextureKind::MultiScale:
        add_centers(base, R, A, (dense ? 2.0 : 3.0) * R, R + R);
        add_centers(base, R / 3.0, A / 3.0, (dense ? 2.0 : 3.0) * R / 3.0, R + R / 3.0);
        break;
      case TextureKind::Scales:
        add_centers(base, R, A, 2.0 * R, 0.0);
        break;
      default:
        break;
    }
  }

  std::size_t feature_count() const {
    std::size_t n = 0;
    for (const CenterSet& set : sets_)
      for (const auto& p : set.patches) n += static_cast<std::size_t>(p->centers.rows());
    return n;
  }

  /// All feature centers and their base normals, set after set.
  void centers(Positions& C, Normals& N) const {
    C.resize(static_cast<Eigen::Index>(feature_count()), 3);
    N.resize(C.rows(), 3);
    Eigen::Index row = 0;
    for (const CenterSet& set : sets_)
      for (const auto& p : set.patches) {
        C.middleRows(row, p->centers.rows()) = p->centers;
        N.middleRows(row, p->normals.rows()) = p->normals;
        row += p->centers.rows();
      }
  }

  void evaluate(int patch, const Vector3d& x, const Frame& frame, double& h, Vector3d& grad) const {
    h = 0.0;
    grad.setZero();
    switch (params_.texture) {
      case TextureKind::None:
        return;
      case TextureKind::Bumps:
      case TextureKind::Domes:
      case TextureKind::MultiScale:
        for (const CenterSet& set : sets_) add_compact(set, patch, x, frame, h, grad);
        return;
      case TextureKind::Scales:
        return add_scales(patch, x, frame, h, grad);
      default:
        return add_lines(x, frame, h, grad);
    }
  }

 private:
  void add_centers(const BaseSurface& base, double radius, double amplitude, double spacing,
                   double margin) {
    CenterSet set;
    set.radius = radius;
    set.amplitude = amplitude;
    for (int p = 0; p < base.patch_count(); ++p) {
      Rng rng(params_.seed, kFeatures, static_cast<std::uint64_t>(sets_.size() * 64 + p));
      std::vector<Vector3d> normals;
      const std::vector<Vector3d> darts = throw_darts(base, p, spacing, margin, rng, normals);
      auto pc = std::make_unique<PatchCenters>();
      pc->centers.resize(static_cast<Eigen::Index>(darts.size()), 3);
      pc->normals.resize(static_cast<Eigen::Index>(darts.size()), 3);
      for (std::size_t i = 0; i < darts.size(); ++i) {
        pc->centers.row(static_cast<Eigen::Index>(i)) = darts[i].transpose();
        pc->normals.row(static_cast<Eigen::Index>(i)) = normals[i].transpose();
        pc->signs.push_back(params_.mixed_signs ? random_sign(params_.seed, next_feature_++) : 1.0);
      }
      if (!darts.empty()) {
        pc->tree = std::make_unique<PointIndex>(pc->centers);
      }
      set.patches.push_back(std::move(pc));
    }
    sets_.push_back(std::move(set));
  }

  // The weight of a feature centered where the base normal is n_c at a point
  // of frame f, on normal-aware shapes: w(q), q = n(b).n_c, a smoothstep from
  // 0 at q = 0 to 1 at q = 1/2, and its gradient w'(q) sum_i k_i (t_i.n_c) t_i
  // (dn/dt_i = k_i t_i).
  void side_weight(const Frame& f, const Vector3d& n_c, double& w, Vector3d& dw) const {
    w = 1.0;
    dw.setZero();
    if (!normal_aware_) return;
    const double q = f.n.dot(n_c);
    if (q >= 0.5) return;
    if (q <= 0.0) {
      w = 0.0;
      return;
    }
    const double t = 2.0 * q;
    w = t * t * (3.0 - 2.0 * t);
    const double dw_dq = 12.0 * t * (1.0 - t);
    dw = dw_dq * (f.k1 * f.t1.dot(n_c) * f.t1 + f.k2 * f.t2.dot(n_c) * f.t2);
  }

  // Bumps and domes: a radial profile g(s), s = d^2/R^2, on the disc s < 1;
  // features of one set never overlap (spacing >= 2R) unless they lie on
  // two sides of a thin part (normal-aware shapes; then the side weight
  // keeps them apart).
  void add_compact(const CenterSet& set, int patch, const Vector3d& x, const Frame& frame,
                   double& h, Vector3d& grad) const {
    const PatchCenters& pc = *set.patches[patch];
    if (!pc.tree) return;
    const double radius = set.radius, radius_sq = radius * radius;
    std::vector<std::pair<std::uint32_t, double>> found;
    pc.tree->within(x.data(), radius, found);
    for (const auto& [j, d_sq] : found) {
      const double s = d_sq / radius_sq;
      if (s >= 1.0) continue;
      double g, dg_ds;
      if (params_.texture == TextureKind::Domes) {
        g = std::sqrt(1.0 - s);
        dg_ds = -0.5 / g;
      } else {
        const double e = std::exp(-2.0 * s);
        g = e * (1.0 - s) * (1.0 - s);
        dg_ds = -2.0 * e * (1.0 - s) * (2.0 - s);
      }
      double w;
      Vector3d dw;
      side_weight(frame, pc.normals.row(j).transpose(), w, dw);
      if (w == 0.0) continue;
      const double a = set.amplitude * pc.signs[j];
      const Vector3d ds_dx = 2.0 * (x - pc.centers.row(j).transpose()) / radius_sq;
      if (w == 1.0) {  // the same expressions as before the weight, for identical output
        h += a * g;
        grad += a * dg_ds * ds_dx;
      } else {
        h += a * g * w;
        grad += a * (dg_ds * w * ds_dx + g * dw);
      }
    }
  }

  // C1 ramp from 0 at e = R to 1 at e = 2R (smoothstep), so that line and
  // cell textures vanish within R of patch borders.
  void border_window(const Frame& frame, double& w, Vector3d& dw) const {
    const double R = params_.size, t = (frame.edge_distance - R) / R;
    w = 1.0;
    dw.setZero();
    if (t >= 1.0) return;
    if (t <= 0.0) {
      w = 0.0;
      return;
    }
    w = t * t * (3.0 - 2.0 * t);
    dw = 6.0 * t * (1.0 - t) / R * frame.edge_gradient;
  }

  // Voronoi cells of the patch's centers. The distance to the cell border of
  // the nearest center c1 is the smallest distance to a bisector plane,
  // (|x - cj|^2 - |x - c1|^2) / (2 |cj - c1|); only centers with
  // |x - cj| < |x - c1| + 2R can bring it below R, where the profile is flat.
  // On normal-aware shapes the cells are those of the lifted points
  // (x, lambda n(x)), lambda = 2R, so that a center on the other side of a
  // thin part (normals opposite: lifted distance >= 4R) never owns a point
  // that has a center of its own side within 2R. Lifted distances are at
  // least the 3D ones, so the 3D searches below still find every candidate.
  void add_scales(int patch, const Vector3d& x, const Frame& frame, double& h,
                  Vector3d& grad) const {
    const PatchCenters& pc = *sets_[0].patches[patch];
    if (!pc.tree) return;
    const double R = params_.size, lambda = normal_aware_ ? 2.0 * R : 0.0;
    auto lifted_sq = [&](std::uint32_t j, double d_sq) {
      return normal_aware_
                 ? d_sq + lambda * lambda * (frame.n - pc.normals.row(j).transpose()).squaredNorm()
                 : d_sq;
    };
    double nearest_sq = 0.0;
    std::uint32_t nearest = pc.tree->nearest(x.data(), &nearest_sq);
    std::vector<std::pair<std::uint32_t, double>> found;
    if (normal_aware_) {
      nearest_sq = lifted_sq(nearest, nearest_sq);
      pc.tree->within(x.data(), std::sqrt(nearest_sq), found);
      for (const auto& [j, d_sq] : found) {
        const double l_sq = lifted_sq(j, d_sq);
        if (l_sq < nearest_sq || (l_sq == nearest_sq && j < nearest))
          nearest_sq = l_sq, nearest = j;
      }
    }
    const Vector3d c1 = pc.centers.row(nearest).transpose();
    const Vector3d n1 = pc.normals.row(nearest).transpose();
    const double search_radius = std::sqrt(nearest_sq) + 2.0 * R;
    pc.tree->within(x.data(), search_radius, found);
    double border = kInfinity;
    Vector3d border_gradient = Vector3d::Zero();
    for (const auto& [j, d_sq] : found) {
      if (j == nearest) continue;
      const Vector3d cj = pc.centers.row(j).transpose();
      if (!normal_aware_) {
        const double length = (cj - c1).norm();
        const double d = (d_sq - nearest_sq) / (2.0 * length);
        if (d < border) border = d, border_gradient = (c1 - cj) / length;
        continue;
      }
      const Vector3d nj = pc.normals.row(j).transpose();
      const double length =
          std::sqrt((cj - c1).squaredNorm() + lambda * lambda * (nj - n1).squaredNorm());
      const double d = (lifted_sq(j, d_sq) - nearest_sq) / (2.0 * length);
      if (d < border) {
        // d(|Y - Yj|^2 - |Y - Y1|^2)/dx along t_i: 2 (c1 - cj).t_i - 2 lambda^2 k_i t_i.(nj - n1).
        const Vector3d dn = nj - n1;
        border = d;
        border_gradient = ((c1 - cj) - lambda * lambda *
                                           (frame.k1 * frame.t1.dot(dn) * frame.t1 +
                                            frame.k2 * frame.t2.dot(dn) * frame.t2)) /
                          length;
      }
    }
    const double gap = params_.layout == TextureLayout::Sparse ? 0.5 * R : 0.0;
    const double t = (border - gap) / (R - gap);
    if (t <= 0.0) return;
    double rho = 1.0;
    Vector3d drho = Vector3d::Zero();
    if (t < 1.0) {
      rho = t * (2.0 - t);
      drho = 2.0 * (1.0 - t) / (R - gap) * border_gradient;
    }
    double w;
    Vector3d dw;
    border_window(frame, w, dw);
    const double a = params_.amplitude * pc.signs[nearest];
    h = a * rho * w;
    grad = a * (drho * w + rho * dw);
  }

  // Parallel ridges or grooves across the direction k: u = k.x, lines at
  // multiples of the period, v the offset from the nearest line.
  void add_lines(const Vector3d& x, const Frame& frame, double& h, Vector3d& grad) const {
    const double R = params_.size;
    const double period = (params_.layout == TextureLayout::Dense ? 2.0 : 4.0) * R;
    const double u = direction_.dot(x), line = std::round(u / period), v = u - line * period;
    if (std::abs(v) >= R) return;
    double rho = 0.0, drho_dv = 0.0;
    switch (params_.texture) {
      case TextureKind::Waves:
        rho = 0.5 * (1.0 + std::cos(kPi * v / R));
        drho_dv = -0.5 * kPi / R * std::sin(kPi * v / R);
        break;
      case TextureKind::VGrooves:
        rho = -(1.0 - std::abs(v) / R);
        drho_dv = (v > 0.0 ? 1.0 : -1.0) / R;
        break;
      default: {  // UGrooves
        const double q = 1.0 - (v / R) * (v / R);
        if (q <= 0.0) return;
        rho = -std::sqrt(q);
        drho_dv = v / (R * R * std::sqrt(q));
        break;
      }
    }
    double w;
    Vector3d dw;
    border_window(frame, w, dw);
    const double sign =
        params_.mixed_signs
            ? random_sign(params_.seed, static_cast<std::uint64_t>(static_cast<std::int64_t>(line)))
            : 1.0;
    const double a = params_.amplitude * sign;
    h = a * rho * w;
    grad = a * (drho_dv * w * direction_ + rho * dw);
  }

  const SynthParams params_;
  const Vector3d direction_;
  const bool normal_aware_;
  std::vector<CenterSet> sets_;
  std::uint64_t next_feature_ = 0;
};

// The displaced surface p = b + h n has tangents (1 + h k_i) t_i + h_i n
// along the principal directions (h_i = dh/dt_i), so its exact normal is
// their cross product, a1 a2 n - a1 h2 t2 - a2 h1 t1 with a_i = 1 + h k_i.
Vector3d textured_normal(const Frame& f, double h, const Vector3d& grad) {
  const double a1 = 1.0 + h * f.k1, a2 = 1.0 + h * f.k2;
  const double h1 = grad.dot(f.t1), h2 = grad.dot(f.t2);
  return (a1 * a2 * f.n - a1 * h2 * f.t2 - a2 * h1 * f.t1).normalized();
}

std::string format_number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

template <class Enum>
Enum parse_name(const std::string& name, const char* what, const char* (*to_name)(Enum),
                int count) {
  std::string valid;
  for (int i = 0; i < count; ++i) {
    const Enum e = static_cast<Enum>(i);
    if (name == to_name(e)) return e;
    valid += std::string(i ? ", " : "") + to_name(e);
  }
  throw std::invalid_argument("unknown " + std::string(what) + " '" + name + "'; expected one of " +
                              valid);
}

}  // namespace

const char* base_shape_name(BaseShape shape) {
  static const char* names[] = {"sphere",    "cube",   "cylinder", "torus", "pyramid", "plane",
                                "ellipsoid", "saddle", "knot",     "blob",  "disc",    "mesh"};
  return names[static_cast<int>(shape)];
}
const char* texture_kind_name(TextureKind texture) {
  static const char* names[] = {"none",  "bumps",     "domes",     "scales",
                                "waves", "v-grooves", "u-grooves", "multiscale"};
  return names[static_cast<int>(texture)];
}
const char* texture_layout_name(TextureLayout layout) {
  return layout == TextureLayout::Sparse ? "sparse" : "dense";
}
BaseShape parse_base_shape(const std::string& name) {
  return parse_name(name, "shape", base_shape_name, 12);
}
TextureKind parse_texture_kind(const std::string& name) {
  return parse_name(name, "texture", texture_kind_name, 8);
}
TextureLayout parse_texture_layout(const std::string& name) {
  return parse_name(name, "layout", texture_layout_name, 2);
}

BaseMesh base_mesh_from_cloud(const PointCloud& cloud) {
  const OtherElement* faces = nullptr;
  for (const OtherElement& e : cloud.other_elements)
    if (e.name == "face") faces = &e;
  if (!faces)
    throw std::invalid_argument(
        "the base mesh file has no 'face' element: it is a point cloud, not a mesh");
  int list = -1;
  for (std::size_t k = 0; k < faces->properties.size(); ++k) {
    const ElementProperty& property = faces->properties[k];
    if (property.is_list && (property.name == "vertex_indices" || property.name == "vertex_index"))
      list = static_cast<int>(k);
  }
  if (list < 0)
    throw std::invalid_argument(
        "the base mesh's 'face' element has no vertex_indices (or vertex_index) list");
  const double vertex_count = static_cast<double>(cloud.size());
  std::vector<Eigen::Matrix<std::int32_t, 1, 3>> triangles;
  for (std::size_t row = 0; row < faces->size(); ++row) {
    // Skip the properties before the list to find its count and items.
    std::uint64_t at = faces->row_offsets[row];
    for (int k = 0; k < list; ++k)
      at += faces->properties[k].is_list ? 1 + static_cast<std::uint64_t>(faces->values[at]) : 1;
    const std::uint64_t count = static_cast<std::uint64_t>(faces->values[at]);
    std::vector<std::int32_t> polygon;
    for (std::uint64_t i = 0; i < count; ++i) {
      const double index = faces->values[at + 1 + i];
      if (!(index >= 0.0 && index < vertex_count))
        throw std::invalid_argument("face " + std::to_string(row) +
                                    " of the base mesh refers to vertex " + format_number(index) +
                                    ", but the mesh has " + std::to_string(cloud.size()) +
                                    " vertices");
      polygon.push_back(static_cast<std::int32_t>(index));
    }
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
      triangles.emplace_back(polygon[0], polygon[i], polygon[i + 1]);
  }
  if (triangles.empty())
    throw std::invalid_argument("the base mesh has no face with three or more vertices");
  BaseMesh mesh;
  mesh.vertices = cloud.positions;
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    mesh.triangles.row(static_cast<Eigen::Index>(t)) = triangles[t];
  return mesh;
}

void validate_synth_params(const SynthParams& p) {
  if (!(p.size >= 0.005 && p.size <= 0.1))
    throw std::invalid_argument(
        "the feature size must be between 0.005 and 0.1 model units (the shapes fit a unit box), "
        "got " +
        format_number(p.size));
  if (!std::isfinite(p.amplitude) || std::abs(p.amplitude) > p.size)
    throw std::invalid_argument("the texture amplitude must be between -size and size (" +
                                format_number(-p.size) + " and " + format_number(p.size) +
                                "), got " + format_number(p.amplitude));
  constexpr std::int64_t kMaxPoints = std::numeric_limits<std::int32_t>::max();
  if (p.points < 1 || p.points > kMaxPoints)
    throw std::invalid_argument("the number of points must be between 1 and 2^31-1, got " +
                                std::to_string(p.points));
  if (p.ground_truth_points < 1 || p.ground_truth_points > kMaxPoints)
    throw std::invalid_argument(
        "the number of ground-truth points must be between 1 and 2^31-1, got " +
        std::to_string(p.ground_truth_points));
  if (!std::isfinite(p.noise) || p.noise < 0.0 || (!p.noise_absolute && p.noise > 0.1))
    throw std::invalid_argument(
        std::string("the noise must be ") +
        (p.noise_absolute ? "a finite number >= 0 (model units)"
                          : "between 0 and 0.1 (a fraction of the bounding-box diagonal)") +
        ", got " + format_number(p.noise));
  if (p.shape == BaseShape::Mesh && (!p.mesh || p.mesh->triangles.rows() == 0))
    throw std::invalid_argument(
        "the mesh shape needs a base mesh with at least one triangle (--base-mesh FILE.ply)");
  if (p.shape == BaseShape::Mesh) {
    const Eigen::Index v = p.mesh->vertices.rows();
    if (p.mesh->triangles.minCoeff() < 0 || p.mesh->triangles.maxCoeff() >= v)
      throw std::invalid_argument("the base mesh has a triangle whose vertex index is not in [0, " +
                                  std::to_string(v) + ")");
    if (!p.mesh->vertices.allFinite())
      throw std::invalid_argument("the base mesh has a vertex with a NaN or infinite coordinate");
  }
  if (static_cast<int>(p.shape) > static_cast<int>(BaseShape::Mesh) ||
      static_cast<int>(p.texture) > static_cast<int>(TextureKind::MultiScale) ||
      static_cast<int>(p.layout) > static_cast<int>(TextureLayout::Dense))
    throw std::invalid_argument("unknown shape, texture or layout value");
}

namespace {

// Textured points first .. first + n - 1 into rows 0 .. n - 1 of out (each
// seeded by its own index, so blocks give the same values as one run).
void sample_points(const SynthParams& params, const BaseSurface& base, const HeightField& field,
                   double noise_sigma, std::int64_t first, Eigen::Index n, SynthesizedShape& out,
                   bool with_base) {
#pragma omp parallel for schedule(static)
  for (Eigen::Index k = 0; k < n; ++k) {
    Rng rng(params.seed, kPoints, static_cast<std::uint64_t>(first + k));
    const int patch = base.choose_patch(rng.uniform());
    Frame frame;
    const Vector3d b = base.sample(patch, rng, frame);
    double h;
    Vector3d grad;
    field.evaluate(patch, b, frame, h, grad);
    Vector3d p = b + h * frame.n;
    if (noise_sigma > 0.0) p += noise_sigma * Vector3d(rng.normal(), rng.normal(), rng.normal());
    out.positions.row(k) = p.transpose();
    out.normals.row(k) = textured_normal(frame, h, grad).transpose();
    if (with_base) {
      out.base_positions.row(k) = b.transpose();
      out.base_normals.row(k) = frame.n.transpose();
    }
    out.texture_heights[static_cast<std::size_t>(k)] = h;
    out.is_texture[static_cast<std::size_t>(k)] = std::abs(h) > kTextureHeightEpsilon ? 1 : 0;
  }
}

void sample_ground_truth(const SynthParams& params, const BaseSurface& base, std::int64_t first,
                         Eigen::Index m, Positions& P, Normals& N) {
#pragma omp parallel for schedule(static)
  for (Eigen::Index k = 0; k < m; ++k) {
    Rng rng(params.seed, kGroundTruth, static_cast<std::uint64_t>(first + k));
    const int patch = base.choose_patch(rng.uniform());
    Frame frame;
    const Vector3d b = base.sample(patch, rng, frame);
    P.row(k) = b.transpose();
    N.row(k) = frame.n.transpose();
  }
}

}  // namespace

SynthesizedShape synthesize_shape(const SynthParams& params) {
  validate_synth_params(params);
  const BaseSurface base(params);
  const HeightField field(params, base);

  SynthesizedShape out;
  out.feature_count = field.feature_count();
  field.centers(out.feature_centers, out.feature_normals);
  out.area = base.total_area();
  out.diagonal = base.diagonal();
  out.degenerate_triangles = base.degenerate_triangles();
  out.noise_sigma = params.noise_absolute ? params.noise : params.noise * out.diagonal;

  const Eigen::Index n = static_cast<Eigen::Index>(params.points);
  out.positions.resize(n, 3);
  out.normals.resize(n, 3);
  out.base_positions.resize(n, 3);
  out.base_normals.resize(n, 3);
  out.texture_heights.resize(static_cast<std::size_t>(n));
  out.is_texture.resize(static_cast<std::size_t>(n));
  sample_points(params, base, field, out.noise_sigma, 0, n, out, true);

  const Eigen::Index m = static_cast<Eigen::Index>(params.ground_truth_points);
  out.ground_truth_positions.resize(m, 3);
  out.ground_truth_normals.resize(m, 3);
  sample_ground_truth(params, base, 0, m, out.ground_truth_positions, out.ground_truth_normals);
  return out;
}

SynthesizedShape synthesize_shape_blocks(
    const SynthParams& params, std::int64_t block,
    const std::function<void(const SynthesizedShape& block, std::int64_t first)>& points,
    const std::function<void(const SynthesizedShape& block, std::int64_t first)>& ground_truth) {
  validate_synth_params(params);
  if (block < 1) throw std::invalid_argument("the synthesis block must hold at least one point");
  const BaseSurface base(params);
  const HeightField field(params, base);
  SynthesizedShape out;
  out.feature_count = field.feature_count();
  field.centers(out.feature_centers, out.feature_normals);
  out.area = base.total_area();
  out.diagonal = base.diagonal();
  out.degenerate_triangles = base.degenerate_triangles();
  out.noise_sigma = params.noise_absolute ? params.noise : params.noise * out.diagonal;
  SynthesizedShape chunk;
  for (std::int64_t first = 0; first < params.points; first += block) {
    const auto n = static_cast<Eigen::Index>(std::min(block, params.points - first));
    chunk.positions.resize(n, 3);
    chunk.normals.resize(n, 3);
    chunk.texture_heights.resize(static_cast<std::size_t>(n));
    chunk.is_texture.resize(static_cast<std::size_t>(n));
    sample_points(params, base, field, out.noise_sigma, first, n, chunk, false);
    points(chunk, first);
  }
  chunk = SynthesizedShape();
  for (std::int64_t first = 0; first < params.ground_truth_points; first += block) {
    const auto m = static_cast<Eigen::Index>(std::min(block, params.ground_truth_points - first));
    chunk.ground_truth_positions.resize(m, 3);
    chunk.ground_truth_normals.resize(m, 3);
    sample_ground_truth(params, base, first, m, chunk.ground_truth_positions,
                        chunk.ground_truth_normals);
    ground_truth(chunk, first);
  }
  return out;
}

TexturedSamples evaluate_texture(const SynthParams& params, const Positions& B) {
  validate_synth_params(params);
  const BaseSurface base(params);
  const HeightField field(params, base);
  TexturedSamples out;
  out.positions.resize(B.rows(), 3);
  out.normals.resize(B.rows(), 3);
  out.heights.resize(static_cast<std::size_t>(B.rows()));
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < B.rows(); ++i) {
    const Vector3d b = B.row(i).transpose();
    const int patch = base.patch_of(b);
    const Frame frame = base.frame(patch, b);
    double h;
    Vector3d grad;
    field.evaluate(patch, b, frame, h, grad);
    out.positions.row(i) = (b + h * frame.n).transpose();
    out.normals.row(i) = textured_normal(frame, h, grad).transpose();
    out.heights[static_cast<std::size_t>(i)] = h;
  }
  return out;
}

}  // namespace detexture
