#include "detexture/geometry/mesh_folds.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace detexture {

InteriorEdges interior_edges(const TriangleIndices& T) {
  struct Sides {
    std::int32_t first = -1, second = -1;
    int count = 0;
  };
  std::unordered_map<std::uint64_t, Sides> map;
  map.reserve(static_cast<std::size_t>(3 * T.rows()));
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int c = 0; c < 3; ++c) {
      const auto a = static_cast<std::uint64_t>(std::min(T(t, c), T(t, (c + 1) % 3)));
      const auto b = static_cast<std::uint64_t>(std::max(T(t, c), T(t, (c + 1) % 3)));
      Sides& s = map[(a << 32) | b];
      (s.count == 0 ? s.first : s.second) = static_cast<std::int32_t>(t);
      ++s.count;
    }
  InteriorEdges edges;
  for (const auto& [key, s] : map)
    if (s.count == 2) {
      edges.left.push_back(std::min(s.first, s.second));
      edges.right.push_back(std::max(s.first, s.second));
    }
  // Hash order is not reproducible across libraries: sort by triangles.
  std::vector<std::size_t> order(edges.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(edges.left[a], edges.right[a]) <
           std::make_pair(edges.left[b], edges.right[b]);
  });
  InteriorEdges sorted;
  for (std::size_t k : order) {
    sorted.left.push_back(edges.left[k]);
    sorted.right.push_back(edges.right[k]);
  }
  return sorted;
}

namespace {

Eigen::Vector3d triangle_normal(const Positions& P, const TriangleIndices& T, Eigen::Index t) {
  const Eigen::Vector3d a = P.row(T(t, 0)).transpose(), b = P.row(T(t, 1)).transpose(),
                        c = P.row(T(t, 2)).transpose();
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

}  // namespace

std::vector<double> dihedral_angles_deg(const Positions& P, const TriangleIndices& T,
                                        const InteriorEdges& edges) {
  std::vector<double> angles(edges.size());
  const auto count = static_cast<std::int64_t>(edges.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t k = 0; k < count; ++k) {
    const auto e = static_cast<std::size_t>(k);
    const Eigen::Vector3d a = triangle_normal(P, T, edges.left[e]);
    const Eigen::Vector3d b = triangle_normal(P, T, edges.right[e]);
    angles[e] =
        (a.isZero() || b.isZero()) ? 0.0 : std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
  }
  return angles;
}

MeshFolds measure_folds(const Positions& P, const TriangleIndices& T, const Positions& reference,
                        double fold_angle_deg) {
  MeshFolds m;
  const InteriorEdges edges = interior_edges(T);
  std::vector<double> angles = dihedral_angles_deg(P, T, edges);
  m.edges = angles.size();
  for (double a : angles) m.folded += a > fold_angle_deg;
  if (!angles.empty()) {
    const std::size_t k = static_cast<std::size_t>(std::floor(0.99 * (angles.size() - 1)));
    std::nth_element(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(k), angles.end());
    m.p99_dihedral_deg = angles[k];
  }
  m.triangles = static_cast<std::size_t>(T.rows());
  std::size_t flipped = 0;
#pragma omp parallel for schedule(static) reduction(+ : flipped)
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    flipped += triangle_normal(P, T, t).dot(triangle_normal(reference, T, t)) < 0.0;
  m.flipped = flipped;
  return m;
}

}  // namespace detexture
