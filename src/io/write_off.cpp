#include "write_off.h"

#include "scalar_codec.h"
#include "write_mesh_common.h"

namespace detexture::io_detail {

void write_off(OutputBuffer& out, const PointCloud& cloud, const std::string& path,
               std::vector<std::string>* notices) {
  const FaceList faces = checked_faces(cloud, path);
  std::vector<int> color;
  for (const char* name : {"red", "green", "blue", "alpha"}) {
    const int k = find_extra(cloud, name);
    if (k < 0) break;
    color.push_back(k);
  }
  if (color.size() < 3) color.clear();
  note_left_out(cloud, color, true, "OFF", notices);
  if (notices && !cloud.comments.empty())
    notices->push_back("OFF has no comments; the " + std::to_string(cloud.comments.size()) +
                       " comments are left out");
  const bool normals = cloud.has_normals();
  std::string& text = out.text();
  text += std::string(color.empty() ? "" : "C") + (normals ? "N" : "") + "OFF\n";
  text += std::to_string(cloud.size()) + " " + std::to_string(faces.size()) + " 0\n";
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    for (int d = 0; d < 3; ++d) {
      if (d > 0) text += ' ';
      append_scalar_text(text, cloud.positions(i, d), ScalarType::Float64);
    }
    if (normals)
      for (int d = 0; d < 3; ++d) {
        text += ' ';
        append_scalar_text(text, cloud.normals(i, d), ScalarType::Float64);
      }
    for (int c : color) {
      const PointProperty& p = cloud.extras[static_cast<std::size_t>(c)];
      text += ' ';
      append_scalar_text(text, p.values[static_cast<std::size_t>(i)],
                         is_integer_type(p.type) ? ScalarType::Float64 : p.type);
    }
    text += '\n';
    out.maybe_flush();
  }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    text += std::to_string(faces.corners(f));
    for (std::size_t k = faces.offsets[f]; k < faces.offsets[f + 1]; ++k)
      text += ' ' + std::to_string(faces.indices[k]);
    text += '\n';
    out.maybe_flush();
  }
}

}  // namespace detexture::io_detail
