// Internal: reading a Wavefront OBJ file held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse the OBJ file bytes (read from path, which names it in errors).
PointCloud read_obj(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
