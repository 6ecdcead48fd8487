#include "detexture/eval/synthesize_shape.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

class BaseSurface {
 public:
  explicit BaseSurface(BaseShape shape) : shape_(shape) {
    const double h = kHalfHeight;
    switch (shape) {
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

  int patch_count() const {
    if (!faces_.empty()) return static_cast<int>(faces_.size());
    return shape_ == BaseShape::Cylinder ? 3 : 1;  // cylinder: side, top cap, bottom cap
  }

  double area(int patch) const {
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

  /// A point uniformly distributed by area on the patch.
  Vector3d sample(int patch, Rng& rng) const {
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

  /// The patch a point of the base surface lies on (ties on an edge, where
  /// h = 0, go to either side).
  int patch_of(const Vector3d& b) const {
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
  std::vector<FlatFace> faces_;
  std::vector<double> cdf_;
};

// The feature centers of one patch with their index (which references the
// matrix, so a PatchCenters never moves once built).
struct PatchCenters {
  Positions centers;
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
// saturated. Sequential, so it depends on the seed only.
std::vector<Vector3d> throw_darts(const BaseSurface& base, int patch, double spacing, double margin,
                                  Rng& rng) {
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
  const double spacing_sq = spacing * spacing;
  for (int failures = 0; failures < kMaxFailures;) {
    const Vector3d x = base.sample(patch, rng);
    bool ok = base.frame(patch, x).edge_distance >= margin;
    const Eigen::Vector3i c = cell_of(x);
    for (int dx = -1; ok && dx <= 1; ++dx)
      for (int dy = -1; ok && dy <= 1; ++dy)
        for (int dz = -1; ok && dz <= 1; ++dz) {
          const auto it = grid.find(key_of(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == grid.end()) continue;
          for (int j : it->second)
            if ((accepted[j] - x).squaredNorm() < spacing_sq) ok = false;
        }
    if (!ok) {
      ++failures;
      continue;
    }
    failures = 0;
    grid[key_of(c)].push_back(static_cast<int>(accepted.size()));
    accepted.push_back(x);
  }
  return accepted;
}

// The height field h on the base surface, as a function of the 3D point b
// on a given patch, with its gradient in R^3 (whose projection on the
// tangent plane is the surface gradient).
class HeightField {
 public:
  HeightField(const SynthParams& params, const BaseSurface& base)
      : params_(params), direction_(Vector3d(1.0, 2.0, 3.0).normalized()) {
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

  void evaluate(int patch, const Vector3d& x, const Frame& frame, double& h, Vector3d& grad) const {
    h = 0.0;
    grad.setZero();
    switch (params_.texture) {
      case TextureKind::None:
        return;
      case TextureKind::Bumps:
      case TextureKind::Domes:
      case TextureKind::MultiScale:
        for (const CenterSet& set : sets_) add_compact(set, patch, x, h, grad);
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
      const std::vector<Vector3d> darts = throw_darts(base, p, spacing, margin, rng);
      auto pc = std::make_unique<PatchCenters>();
      pc->centers.resize(static_cast<Eigen::Index>(darts.size()), 3);
      for (std::size_t i = 0; i < darts.size(); ++i) {
        pc->centers.row(static_cast<Eigen::Index>(i)) = darts[i].transpose();
        pc->signs.push_back(params_.mixed_signs ? random_sign(params_.seed, next_feature_++) : 1.0);
      }
      if (!darts.empty()) {
        pc->tree = std::make_unique<PointIndex>(pc->centers);
      }
      set.patches.push_back(std::move(pc));
    }
    sets_.push_back(std::move(set));
  }

  // Bumps and domes: a radial profile g(s), s = d^2/R^2, on the disc s < 1;
  // features of one set never overlap (spacing >= 2R).
  void add_compact(const CenterSet& set, int patch, const Vector3d& x, double& h,
                   Vector3d& grad) const {
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
      const double a = set.amplitude * pc.signs[j];
      const Vector3d ds_dx = 2.0 * (x - pc.centers.row(j).transpose()) / radius_sq;
      h += a * g;
      grad += a * dg_ds * ds_dx;
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
  void add_scales(int patch, const Vector3d& x, const Frame& frame, double& h,
                  Vector3d& grad) const {
    const PatchCenters& pc = *sets_[0].patches[patch];
    if (!pc.tree) return;
    const double R = params_.size;
    double nearest_sq = 0.0;
    const std::uint32_t nearest = pc.tree->nearest(x.data(), &nearest_sq);
    const Vector3d c1 = pc.centers.row(nearest).transpose();
    const double search_radius = std::sqrt(nearest_sq) + 2.0 * R;
    std::vector<std::pair<std::uint32_t, double>> found;
    pc.tree->within(x.data(), search_radius, found);
    double border = kInfinity;
    Vector3d border_gradient = Vector3d::Zero();
    for (const auto& [j, d_sq] : found) {
      if (j == nearest) continue;
      const Vector3d cj = pc.centers.row(j).transpose();
      const double length = (cj - c1).norm();
      const double d = (d_sq - nearest_sq) / (2.0 * length);
      if (d < border) border = d, border_gradient = (c1 - cj) / length;
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
  static const char* names[] = {"sphere", "cube", "cylinder", "torus", "pyramid", "plane"};
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
  return parse_name(name, "shape", base_shape_name, 6);
}
TextureKind parse_texture_kind(const std::string& name) {
  return parse_name(name, "texture", texture_kind_name, 8);
}
TextureLayout parse_texture_layout(const std::string& name) {
  return parse_name(name, "layout", texture_layout_name, 2);
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
  if (static_cast<int>(p.shape) > static_cast<int>(BaseShape::Plane) ||
      static_cast<int>(p.texture) > static_cast<int>(TextureKind::MultiScale) ||
      static_cast<int>(p.layout) > static_cast<int>(TextureLayout::Dense))
    throw std::invalid_argument("unknown shape, texture or layout value");
}

SynthesizedShape synthesize_shape(const SynthParams& params) {
  validate_synth_params(params);
  const BaseSurface base(params.shape);
  const HeightField field(params, base);

  SynthesizedShape out;
  out.feature_count = field.feature_count();
  out.diagonal = base.diagonal();
  out.noise_sigma = params.noise_absolute ? params.noise : params.noise * out.diagonal;

  const Eigen::Index n = static_cast<Eigen::Index>(params.points);
  out.positions.resize(n, 3);
  out.normals.resize(n, 3);
  out.base_positions.resize(n, 3);
  out.base_normals.resize(n, 3);
  out.texture_heights.resize(static_cast<std::size_t>(n));
  out.is_texture.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    Rng rng(params.seed, kPoints, static_cast<std::uint64_t>(i));
    const int patch = base.choose_patch(rng.uniform());
    const Vector3d b = base.sample(patch, rng);
    const Frame frame = base.frame(patch, b);
    double h;
    Vector3d grad;
    field.evaluate(patch, b, frame, h, grad);
    Vector3d p = b + h * frame.n;
    if (out.noise_sigma > 0.0)
      p += out.noise_sigma * Vector3d(rng.normal(), rng.normal(), rng.normal());
    out.positions.row(i) = p.transpose();
    out.normals.row(i) = textured_normal(frame, h, grad).transpose();
    out.base_positions.row(i) = b.transpose();
    out.base_normals.row(i) = frame.n.transpose();
    out.texture_heights[static_cast<std::size_t>(i)] = h;
    out.is_texture[static_cast<std::size_t>(i)] = std::abs(h) > kTextureHeightEpsilon ? 1 : 0;
  }

  const Eigen::Index m = static_cast<Eigen::Index>(params.ground_truth_points);
  out.ground_truth_positions.resize(m, 3);
  out.ground_truth_normals.resize(m, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < m; ++i) {
    Rng rng(params.seed, kGroundTruth, static_cast<std::uint64_t>(i));
    const int patch = base.choose_patch(rng.uniform());
    const Vector3d b = base.sample(patch, rng);
    out.ground_truth_positions.row(i) = b.transpose();
    out.ground_truth_normals.row(i) = base.frame(patch, b).n.transpose();
  }
  return out;
}

TexturedSamples evaluate_texture(const SynthParams& params, const Positions& B) {
  validate_synth_params(params);
  const BaseSurface base(params.shape);
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
