// How crumpled a mesh is: folded edges, the dihedral angles of its edges,
// and triangles flipped against a reference position of the same mesh.
#pragma once

#include <cstddef>
#include <vector>

#include "detexture/geometry/face_normals.h"
#include "detexture/types.h"

namespace detexture {

/// The edges of T shared by exactly two triangles, each with the two
/// triangles (as rows of T) on either side.
struct InteriorEdges {
  std::vector<std::int32_t> left, right;  ///< triangles, one entry per edge
  std::size_t size() const { return left.size(); }
};
InteriorEdges interior_edges(const TriangleIndices& T);

/// The dihedral angle of every interior edge, degrees: the angle between
/// the normals of its two triangles (0 = flat, 180 = folded flat onto
/// itself); T as orient_triangles leaves it. A degenerate triangle counts as
/// flat with its neighbors (0).
std::vector<double> dihedral_angles_deg(const Positions& P, const TriangleIndices& T,
                                        const InteriorEdges& edges);

struct MeshFolds {
  std::size_t edges = 0;   ///< interior edges
  std::size_t folded = 0;  ///< of them, with a dihedral angle above fold_angle_deg
  std::size_t triangles = 0;
  std::size_t flipped = 0;      ///< triangles whose normal turned > 90° from the reference's
  double p99_dihedral_deg = 0;  ///< 99th percentile of the dihedral angles
};

/// Measure P's mesh T; triangles are compared with the same triangles at
/// `reference` positions (pass P itself for none: flipped = 0).
MeshFolds measure_folds(const Positions& P, const TriangleIndices& T, const Positions& reference,
                        double fold_angle_deg = 60.0);

}  // namespace detexture
