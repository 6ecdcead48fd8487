#include "write_xyz.h"

#include "scalar_codec.h"

namespace detexture::io_detail {

void write_xyz(OutputBuffer& out, const PointCloud& cloud, char separator) {
  // Without normals, a fourth column would read back as a normal, so extras
  // are written only after nx ny nz. XYZ has no types: every value is written
  // as the double it holds.
  const bool normals = cloud.has_normals();
  std::string& text = out.text();
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    for (int d = 0; d < 3; ++d) {
      if (d > 0) text += separator;
      append_scalar_text(text, cloud.positions(i, d), ScalarType::Float64);
    }
    if (normals) {
      for (int d = 0; d < 3; ++d) {
        text += separator;
        append_scalar_text(text, cloud.normals(i, d), ScalarType::Float64);
      }
      for (const PointProperty& extra : cloud.extras) {
        text += separator;
        append_scalar_text(text, extra.values[static_cast<std::size_t>(i)], ScalarType::Float64);
      }
    }
    text += '\n';
    out.maybe_flush();
  }
}

}  // namespace detexture::io_detail
