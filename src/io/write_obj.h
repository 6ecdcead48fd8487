// Internal: writing a Wavefront OBJ file.
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"

namespace detexture::io_detail {

/// Write cloud as OBJ: comments as '#' lines, "v x y z" (with " r g b" when
/// the cloud has red, green and blue extras; uchar colours divided by 255),
/// "vn" per vertex when it has normals, and the faces as "f a//a b//b ..."
/// (1-based; "f a b c" without normals). Notices say what is left out.
void write_obj(OutputBuffer& out, const PointCloud& cloud, const std::string& path,
               std::vector<std::string>* notices);

}  // namespace detexture::io_detail
