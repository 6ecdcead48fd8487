#include "detexture/render/face_triangles.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace detexture {

Triangles face_triangles(const PointCloud& cloud, std::size_t* skipped) {
  if (skipped) *skipped = 0;
  const OtherElement* faces = nullptr;
  for (const OtherElement& e : cloud.other_elements)
    if (e.name == "face") faces = &e;
  if (!faces) return Triangles();

  int list = -1;
  for (std::size_t k = 0; k < faces->properties.size(); ++k) {
    const ElementProperty& p = faces->properties[k];
    if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
      list = static_cast<int>(k);
      break;
    }
  }
  if (list < 0)
    throw std::invalid_argument(
        "the 'face' element has no list property 'vertex_indices' (or 'vertex_index')");

  const double n = static_cast<double>(cloud.size());
  std::vector<std::uint32_t> corners;
  std::size_t dropped = 0;
  for (std::size_t f = 0; f < faces->size(); ++f) {
    // Walk the row to the list: scalars take one value, lists their count + items.
    std::uint64_t at = faces->row_offsets[f];
    for (int k = 0; k < list; ++k)
      at += faces->properties[k].is_list ? 1 + static_cast<std::uint64_t>(faces->values[at]) : 1;
    const auto count = static_cast<std::uint64_t>(faces->values[at]);
    if (count < 3) {
      ++dropped;
      continue;
    }
    const double* v = faces->values.data() + at + 1;
    for (std::uint64_t c = 0; c < count; ++c)
      if (!(v[c] >= 0 && v[c] < n))
        throw std::invalid_argument("face " + std::to_string(f) + " refers to vertex " +
                                    number_text(v[c]) + ", but there are only " +
                                    std::to_string(cloud.size()) + " vertices");
    for (std::uint64_t c = 1; c + 1 < count; ++c) {
      corners.push_back(static_cast<std::uint32_t>(v[0]));
      corners.push_back(static_cast<std::uint32_t>(v[c]));
      corners.push_back(static_cast<std::uint32_t>(v[c + 1]));
    }
  }
  if (skipped) *skipped = dropped;
  Triangles t(static_cast<Eigen::Index>(corners.size() / 3), 3);
  for (std::size_t i = 0; i < corners.size(); ++i) t.data()[i] = corners[i];
  return t;
}

}  // namespace detexture
