// Internal: what the OBJ, OFF, STL and PCD writers share: the faces of the
// cloud, and notices for what a format cannot hold.
#pragma once

#include <string>
#include <vector>

#include "detexture/io/face_list.h"
#include "detexture/io/point_cloud.h"
#include "io_text.h"

namespace detexture::io_detail {

/// The polygons of cloud (empty without faces), as a write error naming path
/// when a corner is not a vertex.
inline FaceList checked_faces(const PointCloud& cloud, const std::string& path) {
  try {
    return face_list(cloud);
  } catch (const std::invalid_argument& e) {
    throw_write_error(path, e.what());
  }
}

/// The index of the extra named name, or -1.
inline int find_extra(const PointCloud& cloud, const char* name) {
  for (std::size_t k = 0; k < cloud.extras.size(); ++k)
    if (cloud.extras[k].name == name) return static_cast<int>(k);
  return -1;
}

/// A notice listing what `format` leaves out of cloud: the extras not in
/// `kept` (by index), elements other than the faces (or all of them when
/// keep_faces is false), and face properties other than the corners.
inline void note_left_out(const PointCloud& cloud, const std::vector<int>& kept_extras,
                          bool keep_faces, const char* format, std::vector<std::string>* notices) {
  if (!notices) return;
  std::string names;
  std::size_t count = 0;
  for (std::size_t k = 0; k < cloud.extras.size(); ++k) {
    bool kept = false;
    for (int i : kept_extras) kept = kept || i == static_cast<int>(k);
    if (kept) continue;
    if (count++ < 6) names += (names.empty() ? "" : ", ") + cloud.extras[k].name;
  }
  if (count > 0)
    notices->push_back(std::string(format) + " cannot hold the vertex properties " + names +
                       (count > 6 ? " and " + std::to_string(count - 6) + " more" : "") +
                       "; they are left out (write .ply to keep them)");
  for (const OtherElement& e : cloud.other_elements) {
    if (e.name == "face" && keep_faces) {
      if (e.properties.size() > 1)
        notices->push_back(std::string(format) +
                           " keeps only the corners of the faces; their other properties are "
                           "left out");
      continue;
    }
    notices->push_back(std::string(format) + " cannot hold the element '" + e.name + "' (" +
                       std::to_string(e.size()) + " rows); it is left out");
  }
}

}  // namespace detexture::io_detail
