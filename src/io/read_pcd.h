// Internal: reading a PCD v0.7 file (Point Cloud Library) held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse the PCD file bytes (read from path, which names it in errors).
PointCloud read_pcd(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
