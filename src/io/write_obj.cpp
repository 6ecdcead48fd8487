#include "write_obj.h"

#include "scalar_codec.h"
#include "write_mesh_common.h"

namespace detexture::io_detail {

void write_obj(OutputBuffer& out, const PointCloud& cloud, const std::string& path,
               std::vector<std::string>* notices) {
  const FaceList faces = checked_faces(cloud, path);
  const int rgb[3] = {find_extra(cloud, "red"), find_extra(cloud, "green"),
                      find_extra(cloud, "blue")};
  const bool colors = rgb[0] >= 0 && rgb[1] >= 0 && rgb[2] >= 0;
  note_left_out(cloud, colors ? std::vector<int>{rgb[0], rgb[1], rgb[2]} : std::vector<int>{}, true,
                "OBJ", notices);
  std::string& text = out.text();
  for (const std::string& comment : cloud.comments) {
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw_write_error(path, "a comment contains a line break");
    text += "# " + comment + "\n";
  }
  const bool normals = cloud.has_normals();
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    text += 'v';
    for (int d = 0; d < 3; ++d) {
      text += ' ';
      append_scalar_text(text, cloud.positions(i, d), ScalarType::Float64);
    }
    if (colors)
      for (int c : rgb) {
        const PointProperty& p = cloud.extras[static_cast<std::size_t>(c)];
        double value = p.values[static_cast<std::size_t>(i)];
        if (p.type == ScalarType::UInt8) value /= 255.0;
        text += ' ';
        append_scalar_text(text, value, ScalarType::Float64);
      }
    text += '\n';
    out.maybe_flush();
  }
  if (normals)
    for (Eigen::Index i = 0; i < cloud.normals.rows(); ++i) {
      text += "vn";
      for (int d = 0; d < 3; ++d) {
        text += ' ';
        append_scalar_text(text, cloud.normals(i, d), ScalarType::Float64);
      }
      text += '\n';
      out.maybe_flush();
    }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    text += 'f';
    for (std::size_t k = faces.offsets[f]; k < faces.offsets[f + 1]; ++k) {
      const std::string index = std::to_string(std::uint64_t(faces.indices[k]) + 1);
      text += ' ' + index;
      if (normals) text += "//" + index;
    }
    text += '\n';
    out.maybe_flush();
  }
}

}  // namespace detexture::io_detail
