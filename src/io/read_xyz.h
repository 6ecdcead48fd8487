// Internal: reading XYZ-style text held in memory.
#pragma once

#include <string>
#include <string_view>

#include "detexture/io/read_point_cloud.h"

namespace detexture::io_detail {

/// Parse rows "x y z [nx ny nz [more...]]" (see read_point_cloud.h for the
/// accepted layout). Normals are returned as stored; the caller normalizes.
PointCloud read_xyz(std::string_view bytes, const std::string& path, ReadReport& report);

}  // namespace detexture::io_detail
