#include "write_stl.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>

#include "scalar_codec.h"
#include "write_mesh_common.h"

namespace detexture::io_detail {

void write_stl(OutputBuffer& out, const PointCloud& cloud, bool ascii, const std::string& path,
               std::vector<std::string>* notices) {
  const FaceList faces = checked_faces(cloud, path);
  if (faces.size() == 0)
    throw_write_error(path,
                      "STL holds triangles, and the cloud has no faces; write .ply, .xyz or "
                      ".pcd for a point cloud");
  std::size_t triangles = 0, polygons = 0;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (faces.corners(f) < 3) continue;
    triangles += faces.corners(f) - 2;
    polygons += faces.corners(f) > 3;
  }
  if (triangles > std::numeric_limits<std::uint32_t>::max())
    throw_write_error(path, "more than 2^32 - 1 triangles do not fit a binary STL");
  note_left_out(cloud, {}, true, "STL", notices);
  if (notices) {
    if (cloud.has_normals())
      notices->push_back(
          "STL holds one normal per triangle, none per vertex; the vertex normals "
          "are left out");
    if (polygons > 0)
      notices->push_back(std::to_string(polygons) +
                         " polygons of more than 3 corners are split into triangles");
    if (!ascii && cloud.position_type != ScalarType::Float32)
      notices->push_back(
          "binary STL stores single precision: coordinates are rounded to float "
          "(--encoding ascii keeps them exactly)");
  }
  const double float_max = std::numeric_limits<float>::max();
  if (!ascii && cloud.positions.size() > 0 && cloud.positions.cwiseAbs().maxCoeff() > float_max)
    throw_write_error(path, "a coordinate is beyond float's range, which binary STL stores");
  std::string& text = out.text();
  if (ascii) {
    text += "solid detexture\n";
  } else {
    char header[80] = {};
    std::strncpy(header, "binary STL written by detexture", sizeof header - 1);
    out.append(header, 80);
    unsigned char count[4];
    store_bytes(count, static_cast<std::uint32_t>(triangles), !host_is_little_endian());
    out.append(count, 4);
  }
  const bool swap = !host_is_little_endian();
  auto corner = [&](std::size_t k) {
    return Eigen::Vector3d(cloud.positions.row(static_cast<Eigen::Index>(faces.indices[k])));
  };
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const std::size_t first = faces.offsets[f];
    for (std::size_t k = first + 1; k + 1 < faces.offsets[f + 1]; ++k) {
      const Eigen::Vector3d p[3] = {corner(first), corner(k), corner(k + 1)};
      Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
      n = n.norm() > 0 ? Eigen::Vector3d(n / n.norm()) : Eigen::Vector3d::Zero();
      if (ascii) {
        text += "facet normal";
        for (int d = 0; d < 3; ++d) {
          text += ' ';
          append_scalar_text(text, n[d], ScalarType::Float64);
        }
        text += "\n outer loop\n";
        for (const Eigen::Vector3d& q : p) {
          text += "  vertex";
          for (int d = 0; d < 3; ++d) {
            text += ' ';
            append_scalar_text(text, q[d], ScalarType::Float64);
          }
          text += '\n';
        }
        text += " endloop\nendfacet\n";
      } else {
        unsigned char facet[50] = {};
        for (int d = 0; d < 3; ++d) store_bytes(facet + 4 * d, static_cast<float>(n[d]), swap);
        for (int c = 0; c < 3; ++c)
          for (int d = 0; d < 3; ++d)
            store_bytes(facet + 12 + 12 * c + 4 * d, static_cast<float>(p[c][d]), swap);
        out.append(facet, 50);
      }
      out.maybe_flush();
    }
  }
  if (ascii) text += "endsolid detexture\n";
}

}  // namespace detexture::io_detail
