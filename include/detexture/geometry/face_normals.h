// Vertex normals of a mesh from its faces, with no PCA: the faces already
// say where the surface is. Used by remove_texture when the input has faces.
#pragma once

#include <cstddef>
#include <cstdint>

#include "detexture/io/face_list.h"
#include "detexture/types.h"

namespace detexture {

/// #T by 3 rows of vertex indices, counter-clockwise seen from the side the
/// triangle's normal points to.
using TriangleIndices = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// The polygons of faces split into fans around their first corner; polygons
/// of fewer than 3 corners are skipped.
TriangleIndices triangulate_faces(const FaceList& faces);

/// Flip triangles of T so that two triangles sharing an edge (shared by
/// exactly two) run along it in opposite directions, one edge-connected
/// component at a time (breadth-first from its first triangle). Then each
/// component whose signed volume, about its vertices' centroid, is negative
/// is flipped whole, so a closed surface faces outwards; an open one keeps
/// the winding most of its triangles had. Returns the number of triangles
/// flipped. Non-manifold edges (3 or more triangles) do not propagate the
/// orientation.
std::size_t orient_triangles(const Positions& P, TriangleIndices& T);

enum class FaceWeighting { Angle, Area };

struct FaceNormalsParams {
  /// Weight of each triangle in its corners' normals: the corner angle
  /// (Thürmer and Wüthrich 1998; independent of how a polygon is split) or
  /// the triangle's area.
  FaceWeighting weighting = FaceWeighting::Angle;
};

/// Unit normals of the vertices of P (#P by 3) from the triangles T (as
/// orient_triangles leaves them): the weighted sum of the normals of the
/// triangles around each vertex. A vertex in no triangle of non-zero area
/// gets (0, 0, 0) and is counted in *isolated (if given); the pipeline then
/// estimates its normal from its neighbors (orient_normals.h).
Normals face_normals(const Positions& P, const TriangleIndices& T,
                     const FaceNormalsParams& params = {}, std::size_t* isolated = nullptr);

}  // namespace detexture
