// Internal: the header of a PCD v0.7 file (Point Cloud Library), shared by
// the reader and the writer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "detexture/io/point_cloud.h"

namespace detexture::io_detail {

enum class PcdData { Ascii, Binary, BinaryCompressed };

struct PcdField {
  std::string name;
  ScalarType type = ScalarType::Float32;
  int count = 1;
  std::size_t offset = 0;  ///< bytes from the start of a point (binary layout)
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0, height = 1, points = 0;
  double viewpoint[7] = {0, 0, 0, 1, 0, 0, 0};
  PcdData data = PcdData::Ascii;
  std::size_t point_bytes = 0;
  std::size_t data_offset = 0;  ///< first byte after the DATA line
  std::size_t data_line = 0;    ///< line number of the first data line
  std::vector<std::string> comments;
};

/// Parse the header; throws std::runtime_error naming path and line.
PcdHeader parse_pcd_header(std::string_view bytes, const std::string& path);

/// The PCD letter (I, U, F) and size of a scalar type.
char pcd_type_letter(ScalarType type);

}  // namespace detexture::io_detail
