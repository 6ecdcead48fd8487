// Internal: writing an STL file.
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"

namespace detexture::io_detail {

/// Write the faces of cloud as STL triangles (polygons split into fans
/// around their first corner), binary (float coordinates) or ascii (exact
/// shortest decimals), each with the unit normal of its corners' cross
/// product. Throws std::runtime_error naming path when the cloud has no
/// faces, or a binary file would overflow float. Notices say what is lost.
void write_stl(OutputBuffer& out, const PointCloud& cloud, bool ascii, const std::string& path,
               std::vector<std::string>* notices);

}  // namespace detexture::io_detail
