// Internal: writing an OFF file.
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"

namespace detexture::io_detail {

/// Write cloud as OFF, NOFF (with normals), COFF (with red, green, blue
/// [alpha] extras) or CNOFF: one vertex per line "x y z [nx ny nz] [r g b
/// [a]]", then one face per line "n i1 ... in" (0-based). Notices say what
/// is left out (other extras, comments).
void write_off(OutputBuffer& out, const PointCloud& cloud, const std::string& path,
               std::vector<std::string>* notices);

}  // namespace detexture::io_detail
