// Internal: writing a PCD v0.7 file (Point Cloud Library).
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "output_buffer.h"
#include "pcd_header.h"

namespace detexture::io_detail {

/// Write cloud as PCD v0.7, unorganized (HEIGHT 1): fields x y z (F 4 when
/// the cloud's position_type is Float32 and every value fits, else F 8),
/// normal_x normal_y normal_z, rgb (or rgba) packed from uchar red, green,
/// blue (and alpha) extras as PCL does (U 4, 0xAARRGGBB), then every other
/// extra in its type. Comments become '#' lines. Throws std::runtime_error
/// naming path for a property name PCD cannot hold (blank, duplicate).
void write_pcd(OutputBuffer& out, const PointCloud& cloud, PcdData data, const std::string& path,
               std::vector<std::string>* notices);

}  // namespace detexture::io_detail
