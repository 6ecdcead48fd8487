// Internal: reading an OFF file (OFF, COFF, NOFF, CNOFF) held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse the OFF file bytes (read from path, which names it in errors).
PointCloud read_off(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
