// Small shapes for tests whose answers can be worked out by hand.
#pragma once

#include <algorithm>
#include <cmath>

#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"
#include "detexture/types.h"

namespace detexture::test {

/// A unit square z = h(x, y) sampled on a regular grid of `side` x `side`
/// points, with one Gaussian bump h = amplitude·exp(-|q - c|²/(2 width²))
/// centred at c = (0.5, 0.5). Normals are the exact normals of the bumpy
/// surface; `height` gets h per point.
struct BumpyPlane {
  Positions P;
  Normals N;
  Eigen::VectorXd height;
};

inline BumpyPlane bumpy_plane(int side, double amplitude, double width) {
  BumpyPlane s;
  const int n = side * side;
  s.P.resize(n, 3);
  s.N.resize(n, 3);
  s.height.resize(n);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const int i = a * side + b;
      const double x = a / (side - 1.0), y = b / (side - 1.0);
      const double dx = x - 0.5, dy = y - 0.5;
      const double h = amplitude * std::exp(-(dx * dx + dy * dy) / (2 * width * width));
      s.P.row(i) << x, y, h;
      s.height(i) = h;
      // ∇h = -h (dx, dy) / width²; n ∝ (-h_x, -h_y, 1).
      const Eigen::RowVector3d n(h * dx / (width * width), h * dy / (width * width), 1.0);
      s.N.row(i) = n.normalized();
    }
  return s;
}

}  // namespace detexture::test

namespace detexture::test {

/// Angle in degrees between two unit row vectors.
inline double angle_deg(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
}

/// A unit square folded along x = 0.5 by `angle_deg`: the half x <= 0.5 lies
/// in z = 0, the other half rises at the given angle. Sampled on a side x side
/// grid of (x, y) before folding; exact face normals, the crease line taking
/// the flat face's.
inline BumpyPlane folded_plane(int side, double angle_deg) {
  BumpyPlane s;
  const int n = side * side;
  s.P.resize(n, 3);
  s.N.resize(n, 3);
  s.height.setZero(n);
  const double t = angle_deg * M_PI / 180.0;
  const Eigen::RowVector3d rising(-std::sin(t), 0.0, std::cos(t));
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      const int i = a * side + b;
      const double x = a / (side - 1.0), y = b / (side - 1.0);
      if (x <= 0.5) {
        s.P.row(i) << x, y, 0.0;
        s.N.row(i) << 0.0, 0.0, 1.0;
      } else {
        s.P.row(i) << 0.5 + (x - 0.5) * std::cos(t), y, (x - 0.5) * std::sin(t);
        s.N.row(i) = rising;
      }
    }
  return s;
}

/// `n` points spread evenly over a sphere of radius `radius` centred at
/// `center` (Fibonacci lattice), with outward normals.
inline BumpyPlane fibonacci_sphere(int n, double radius,
                                   const Eigen::RowVector3d& center = Eigen::RowVector3d::Zero()) {
  BumpyPlane s;
  s.P.resize(n, 3);
  s.N.resize(n, 3);
  s.height.setZero(n);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double rho = std::sqrt(1.0 - z * z);
    const Eigen::RowVector3d u(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    s.N.row(i) = u;
    s.P.row(i) = center + radius * u;
  }
  return s;
}

/// The six faces of the cube [-0.5, 0.5]^3, each sampled at the centers of an
/// m by m grid (6 m² points, face by face), with each point's outward face
/// normal.
inline BumpyPlane cube_faces(int m) {
  BumpyPlane s;
  s.P.resize(6 * m * m, 3);
  s.N.resize(6 * m * m, 3);
  s.height.setZero(6 * m * m);
  int row = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2)
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) {
          Eigen::RowVector3d p, n = Eigen::RowVector3d::Zero();
          p(axis) = 0.5 * side;
          p((axis + 1) % 3) = (a + 0.5) / m - 0.5;
          p((axis + 2) % 3) = (b + 0.5) / m - 0.5;
          n(axis) = side;
          s.P.row(row) = p;
          s.N.row(row++) = n;
        }
  return s;
}

// synth's torus with dense waves 0.04 wide and 0.016 high (30k points), and
// the suites' rule for it: r = σs = 1.5 × 0.04.
inline SynthesizedShape wavy_torus() {
  SynthParams sp;
  sp.shape = BaseShape::Torus;
  sp.texture = TextureKind::Waves;
  sp.layout = TextureLayout::Dense;
  sp.size = 0.04;
  sp.amplitude = 0.016;
  sp.points = 30000;
  sp.ground_truth_points = 1;
  return synthesize_shape(sp);
}

inline RemoveTextureParams wavy_torus_params() {
  RemoveTextureParams p;
  p.radius = Length{1.5 * 0.04, Length::Unit::Absolute};
  p.sigma_s = p.radius;
  p.threads = 2;
  return p;
}

}  // namespace detexture::test
