// Internal: the header of a PLY file, parsed and checked.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture::io_detail {

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;  ///< the items' type, for a list
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;  ///< only for lists; always an integer type
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;  ///< at least one
  std::size_t line = 0;                 ///< line of the "element" keyword
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;   ///< unique names
  std::vector<std::string> comments;  ///< "comment" text; "obj_info" lines kept whole
  std::size_t data_offset = 0;        ///< first byte after "end_header" and its line ending
  std::size_t data_line = 0;          ///< line number of the first data line (ascii)
  std::vector<std::string> notices;   ///< unknown lines before the first element, kept
};

/// The type named by a PLY type name (both spellings: "uchar" and "uint8").
bool scalar_type_from_name(std::string_view name, ScalarType* type);

/// Parse the header at the start of bytes. Throws std::runtime_error naming
/// path and the line for a missing "ply" magic line, a missing or unknown
/// format line, an unknown type or keyword, a malformed element or property
/// line, a duplicate name, an element without properties, a missing
/// "end_header", or a header longer than kMaxPlyHeaderBytes. An unknown line
/// before the first element (old Blender's bare "Created by ...") is kept as a
/// comment and noted; after it, it is an error. Linear in the header's size.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& path);

}  // namespace detexture::io_detail
