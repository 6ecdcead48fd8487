// Internal: writing a PLY file.
#pragma once

#include <string>

#include "detexture/io/write_point_cloud.h"
#include "output_buffer.h"

namespace detexture::io_detail {

/// Write cloud as PLY: the vertex element first (x y z and nx ny nz as
/// double, then the extras in their types), then the other elements in
/// order. Throws std::runtime_error naming path for a name that cannot be
/// written, an extra value that does not fit its type, or an element row
/// whose values do not match its properties.
void write_ply(OutputBuffer& out, const PointCloud& cloud, PlyEncoding encoding,
               const std::string& path);

}  // namespace detexture::io_detail
