// Internal: reading a PLY file held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse the PLY file bytes (read from path, which names it in errors).
/// Normals are returned as stored; the caller normalizes them.
PointCloud read_ply(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
