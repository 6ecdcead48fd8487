#include "detexture/geometry/face_normals.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>
#include <vector>

namespace detexture {

TriangleIndices triangulate_faces(const FaceList& faces) {
  std::size_t count = 0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (faces.corners(f) >= 3) count += faces.corners(f) - 2;
  TriangleIndices T(static_cast<Eigen::Index>(count), 3);
  Eigen::Index t = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::size_t first = faces.offsets[f];
    for (std::size_t k = first + 1; k + 1 < faces.offsets[f + 1]; ++k)
      T.row(t++) << static_cast<std::int32_t>(faces.indices[first]),
          static_cast<std::int32_t>(faces.indices[k]),
          static_cast<std::int32_t>(faces.indices[k + 1]);
  }
  return T;
}

namespace {

std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}

}  // namespace

std::size_t orient_triangles(const Positions& P, TriangleIndices& T) {
  const Eigen::Index m = T.rows();
  // For every edge, the triangles that use it (up to two kept; a third marks
  // it non-manifold).
  std::unordered_map<std::uint64_t, std::pair<std::int64_t, std::int64_t>> edges;
  std::unordered_map<std::uint64_t, int> uses;
  edges.reserve(static_cast<std::size_t>(3 * m));
  for (Eigen::Index t = 0; t < m; ++t)
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t key = edge_key(T(t, c), T(t, (c + 1) % 3));
      auto [it, added] = edges.try_emplace(key, t, -1);
      if (!added && it->second.second < 0) it->second.second = t;
      ++uses[key];
    }
  auto runs = [&](Eigen::Index t, std::int32_t a, std::int32_t b) {  // a -> b in t?
    for (int c = 0; c < 3; ++c)
      if (T(t, c) == a && T(t, (c + 1) % 3) == b) return true;
    return false;
  };
  std::vector<std::int64_t> component(static_cast<std::size_t>(m), -1);
  std::vector<std::uint8_t> flipped(static_cast<std::size_t>(m), 0);
  std::vector<Eigen::Index> queue;
  std::size_t flips = 0;
  std::int64_t components = 0;
  std::vector<std::vector<Eigen::Index>> members;
  for (Eigen::Index seed = 0; seed < m; ++seed) {
    if (component[seed] >= 0) continue;
    members.emplace_back();
    component[seed] = components;
    queue.assign(1, seed);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Eigen::Index t = queue[q];
      members.back().push_back(t);
      for (int c = 0; c < 3; ++c) {
        const std::int32_t a = T(t, c), b = T(t, (c + 1) % 3);
        const std::uint64_t key = edge_key(a, b);
        if (uses[key] != 2) continue;
        const auto& pair = edges[key];
        const Eigen::Index u = pair.first == t ? pair.second : pair.first;
        if (u < 0 || component[u] >= 0) continue;
        component[u] = components;
        if (runs(u, a, b)) {  // same direction: u must turn around
          std::swap(T(u, 1), T(u, 2));
          flipped[u] ^= 1;
        }
        queue.push_back(u);
      }
    }
    ++components;
  }
  for (const auto& part : members) {
    Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
    for (Eigen::Index t : part)
      for (int c = 0; c < 3; ++c) centroid += P.row(T(t, c));
    centroid /= 3.0 * part.size();
    double volume = 0.0;
    std::size_t kept = 0;
    for (Eigen::Index t : part) {
      const Eigen::Vector3d a = (P.row(T(t, 0)) - centroid).transpose();
      const Eigen::Vector3d b = (P.row(T(t, 1)) - centroid).transpose();
      const Eigen::Vector3d c = (P.row(T(t, 2)) - centroid).transpose();
      volume += a.dot(b.cross(c));
      kept += !flipped[t];
    }
    // Closed (no boundary edge): by volume; open: as most triangles were.
    bool closed = true;
    for (Eigen::Index t : part)
      for (int c = 0; c < 3 && closed; ++c)
        closed = uses[edge_key(T(t, c), T(t, (c + 1) % 3))] == 2;
    const bool turn = closed ? volume < 0.0 : 2 * kept < part.size();
    for (Eigen::Index t : part) {
      if (turn) {
        std::swap(T(t, 1), T(t, 2));
        flipped[t] ^= 1;
      }
      flips += flipped[t];
    }
  }
  return flips;
}

Normals face_normals(const Positions& P, const TriangleIndices& T, const FaceNormalsParams& params,
                     std::size_t* isolated) {
  Normals N = Normals::Zero(P.rows(), 3);
  for (Eigen::Index t = 0; t < T.rows(); ++t) {
    const Eigen::Vector3d p[3] = {P.row(T(t, 0)).transpose(), P.row(T(t, 1)).transpose(),
                                  P.row(T(t, 2)).transpose()};
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const double norm = cross.norm();
    if (!(norm > 0.0)) continue;
    const Eigen::Vector3d n = cross / norm;
    for (int c = 0; c < 3; ++c) {
      double weight = 0.5 * norm;  // area
      if (params.weighting == FaceWeighting::Angle) {
        const Eigen::Vector3d u = p[(c + 1) % 3] - p[c], v = p[(c + 2) % 3] - p[c];
        weight = std::atan2(u.cross(v).norm(), u.dot(v));
      }
      N.row(T(t, c)) += weight * n.transpose();
    }
  }
  std::size_t zero = 0;
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double norm = N.row(i).norm();
    if (norm > 0.0 && std::isfinite(norm))
      N.row(i) /= norm;
    else
      N.row(i).setZero(), ++zero;
  }
  if (isolated) *isolated = zero;
  return N;
}

}  // namespace detexture
