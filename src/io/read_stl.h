// Internal: reading an STL file (ascii or binary) held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse the STL file bytes (read from path, which names it in errors).
/// Corners at exactly the same position become one vertex.
PointCloud read_stl(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
