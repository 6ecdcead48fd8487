// The triangles of a mesh read from PLY, for drawing it.
#pragma once

#include <cstddef>

#include "detexture/io/point_cloud.h"
#include "detexture/render/render_point_cloud.h"

namespace detexture {

/// The faces of cloud's "face" element as triangles: the list property
/// "vertex_indices" (or "vertex_index", the older spelling) of each row,
/// polygons of more than three corners split into a fan around the first.
/// Returns no triangles when the cloud has no face element. Faces of fewer
/// than three corners are data, not errors: they are skipped and counted in
/// *skipped (if given).
///
/// Throws std::invalid_argument with a sentence when the face element has no
/// such list property, or a face refers to a vertex that does not exist.
Triangles face_triangles(const PointCloud& cloud, std::size_t* skipped = nullptr);

}  // namespace detexture
