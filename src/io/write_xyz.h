// Internal: writing XYZ text.
#pragma once

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"

namespace detexture::io_detail {

/// One row per point: x y z, then nx ny nz and the extras if the cloud has
/// normals, values separated by separator (' ' or ','), each in the shortest
/// text that reads back exactly.
void write_xyz(OutputBuffer& out, const PointCloud& cloud, char separator);

}  // namespace detexture::io_detail
