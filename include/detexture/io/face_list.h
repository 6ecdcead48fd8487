// The polygons of a mesh, as the readers of every format keep them: the
// "face" element of PointCloud::other_elements with a list property
// "vertex_indices" (the PLY convention), so that faces live in one place on
// the cloud, whatever the file format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/io/point_cloud.h"

namespace detexture {

/// Polygons in compressed rows: polygon f has the corners
/// indices[offsets[f]] ... indices[offsets[f+1] - 1], each a row of the
/// cloud's positions.
struct FaceList {
  std::vector<std::size_t> offsets{0};  ///< #F+1
  std::vector<std::uint32_t> indices;   ///< corners of every polygon, in order
  std::size_t size() const { return offsets.size() - 1; }
  std::size_t corners(std::size_t f) const { return offsets[f + 1] - offsets[f]; }
  void add(const std::uint32_t* corner, std::size_t count) {
    indices.insert(indices.end(), corner, corner + count);
    offsets.push_back(indices.size());
  }
};

/// Whether cloud has a "face" element with a vertex_indices (or the older
/// vertex_index) list property.
bool has_faces(const PointCloud& cloud);

/// The polygons of cloud's "face" element (empty when it has none: see
/// has_faces). Throws std::invalid_argument with a sentence when a corner is
/// not a vertex of the cloud (negative, not whole, or >= #P).
FaceList face_list(const PointCloud& cloud);

/// Replace (or add) cloud's "face" element by one holding only the list
/// vertex_indices: int32 items with a uint8 count, or a uint32 count when a
/// polygon has more than 255 corners.
void set_face_list(PointCloud& cloud, const FaceList& faces);

}  // namespace detexture
