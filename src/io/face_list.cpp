#include "detexture/io/face_list.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace detexture {
namespace {

const OtherElement* face_element(const PointCloud& cloud, int* list) {
  for (const OtherElement& e : cloud.other_elements) {
    if (e.name != "face") continue;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const ElementProperty& p = e.properties[k];
      if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        *list = static_cast<int>(k);
        return &e;
      }
    }
  }
  return nullptr;
}

}  // namespace

bool has_faces(const PointCloud& cloud) {
  int list = -1;
  return face_element(cloud, &list) != nullptr;
}

FaceList face_list(const PointCloud& cloud) {
  FaceList faces;
  int list = -1;
  const OtherElement* element = face_element(cloud, &list);
  if (!element) return faces;
  const double vertex_count = static_cast<double>(cloud.size());
  faces.offsets.reserve(element->size() + 1);
  for (std::size_t row = 0; row < element->size(); ++row) {
    // Skip the properties before the list to find its count and items.
    std::uint64_t at = element->row_offsets[row];
    for (int k = 0; k < list; ++k)
      at +=
          element->properties[k].is_list ? 1 + static_cast<std::uint64_t>(element->values[at]) : 1;
    const auto count = static_cast<std::uint64_t>(element->values[at]);
    for (std::uint64_t i = 0; i < count; ++i) {
      const double index = element->values[at + 1 + i];
      if (!(index >= 0.0 && index < vertex_count && index == std::floor(index)))
        throw std::invalid_argument("face " + std::to_string(row) + " refers to vertex " +
                                    std::to_string(index) + ", but the mesh has " +
                                    std::to_string(cloud.size()) + " vertices");
      faces.indices.push_back(static_cast<std::uint32_t>(index));
    }
    faces.offsets.push_back(faces.indices.size());
  }
  return faces;
}

void set_face_list(PointCloud& cloud, const FaceList& faces) {
  OtherElement element;
  element.name = "face";
  std::size_t largest = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) largest = std::max(largest, faces.corners(f));
  element.properties.push_back({"vertex_indices", ScalarType::Int32, true,
                                largest > 255 ? ScalarType::UInt32 : ScalarType::UInt8});
  element.row_offsets.reserve(faces.size() + 1);
  element.values.reserve(faces.indices.size() + faces.size());
  element.row_offsets.push_back(0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    element.values.push_back(static_cast<double>(faces.corners(f)));
    for (std::size_t k = faces.offsets[f]; k < faces.offsets[f + 1]; ++k)
      element.values.push_back(static_cast<double>(faces.indices[k]));
    element.row_offsets.push_back(element.values.size());
  }
  for (OtherElement& e : cloud.other_elements)
    if (e.name == "face") {
      e = std::move(element);
      return;
    }
  cloud.other_elements.push_back(std::move(element));
}

}  // namespace detexture
