#include "read_obj.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "detexture/io/face_list.h"
#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// "v/vt/vn", "v//vn", "v/vt" or "v": the 1-based (or negative, relative to
// the end) indices; 0 where absent. False when the corner is malformed.
bool parse_corner(std::string_view token, std::int64_t out[3]) {
  out[0] = out[1] = out[2] = 0;
  for (int part = 0; part < 3; ++part) {
    const std::size_t slash = token.find('/');
    const std::string_view field = token.substr(0, slash);
    if (!field.empty()) {
      const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), out[part]);
      if (ec != std::errc() || ptr != field.data() + field.size() || out[part] == 0) return false;
    } else if (part == 0) {
      return false;
    }
    if (slash == std::string_view::npos) return true;
    token.remove_prefix(slash + 1);
  }
  return false;  // more than two slashes
}

// Resolve a 1-based or negative OBJ index against count items; -1 if invalid.
std::int64_t resolve(std::int64_t index, std::size_t count) {
  const auto n = static_cast<std::int64_t>(count);
  const std::int64_t i = index > 0 ? index - 1 : n + index;
  return i >= 0 && i < n ? i : -1;
}

}  // namespace

PointCloud read_obj(std::string_view bytes, const std::string& path, ReadReport& report) {
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);  // UTF-8 byte order mark
  TextLines lines(bytes, 1);
  std::string_view line;
  std::vector<std::string_view> tokens;
  std::vector<double> v, vn, colors;  // 3 per vertex / normal / coloured vertex
  std::size_t colored = 0, texcoords = 0, points_lines = 0, line_lines = 0;
  FaceList faces;
  std::vector<std::int64_t> corner_normal;     // per face corner, -1 = none
  std::map<std::string, std::size_t> ignored;  // keyword -> lines
  std::vector<std::uint32_t> polygon;
  std::vector<std::int64_t> polygon_normals;
  while (lines.next(&line)) {
    if (line.size() > kMaxTextLineBytes)
      throw_read_error(path, at_line(lines.line()),
                       "the line is longer than " + std::to_string(kMaxTextLineBytes >> 20) +
                           " MiB; this is not an OBJ file the reader accepts");
    if (std::memchr(line.data(), '\0', line.size()))
      throw_read_error(path, at_line(lines.line()),
                       "a NUL byte; this is binary data (or UTF-16 text), not an OBJ file");
    line = line.substr(0, line.find('#'));
    split_whitespace(line, &tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    auto numbers = [&](std::size_t from, std::vector<double>& out, const char* what) {
      for (std::size_t k = from; k < tokens.size(); ++k) {
        double x = 0.0;
        if (!parse_double(tokens[k], &x))
          throw_read_error(path, at_line(lines.line()),
                           quoted(tokens[k]) + " is not a number (" + what + ")");
        if (!std::isfinite(x))
          throw_read_error(path, at_line(lines.line()),
                           std::string("a NaN or infinite value (") + what +
                               "); such vertices are refused, not dropped");
        out.push_back(x);
      }
    };
    if (key == "v") {
      const std::size_t n = tokens.size() - 1;
      if (n != 3 && n != 4 && n != 6)
        throw_read_error(path, at_line(lines.line()),
                         "a vertex with " + std::to_string(n) +
                             " values; expected x y z, x y z w or x y z r g b");
      std::vector<double> values;
      numbers(1, values, "vertex");
      v.insert(v.end(), values.begin(), values.begin() + 3);
      if (n == 6) {
        // Colours are kept only when every vertex has one; a vertex before
        // the first coloured one is padded and the colours are dropped below.
        colors.resize(3 * (v.size() / 3 - 1));
        colors.insert(colors.end(), values.begin() + 3, values.end());
        ++colored;
      }
    } else if (key == "vn") {
      if (tokens.size() != 4)
        throw_read_error(
            path, at_line(lines.line()),
            "a normal with " + std::to_string(tokens.size() - 1) + " values; expected vn nx ny nz");
      numbers(1, vn, "normal");
    } else if (key == "vt") {
      ++texcoords;
    } else if (key == "f") {
      if (tokens.size() < 4)
        throw_read_error(path, at_line(lines.line()),
                         "a face with " + std::to_string(tokens.size() - 1) +
                             " corners; a face needs at least 3");
      polygon.clear();
      polygon_normals.clear();
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        std::int64_t index[3];
        if (!parse_corner(tokens[k], index))
          throw_read_error(path, at_line(lines.line()),
                           quoted(tokens[k]) + " is not a face corner (v, v/vt, v//vn or v/vt/vn)");
        const std::int64_t vi = resolve(index[0], v.size() / 3);
        if (vi < 0)
          throw_read_error(path, at_line(lines.line()),
                           "corner " + quoted(tokens[k]) + " refers to vertex " +
                               std::to_string(index[0]) + ", but " + std::to_string(v.size() / 3) +
                               " vertices are defined before this line");
        std::int64_t ni = -1;
        if (index[2] != 0) {
          ni = resolve(index[2], vn.size() / 3);
          if (ni < 0)
            throw_read_error(path, at_line(lines.line()),
                             "corner " + quoted(tokens[k]) + " refers to normal " +
                                 std::to_string(index[2]) + ", but " +
                                 std::to_string(vn.size() / 3) +
                                 " normals are defined before this line");
        }
        polygon.push_back(static_cast<std::uint32_t>(vi));
        polygon_normals.push_back(ni);
      }
      faces.add(polygon.data(), polygon.size());
      corner_normal.insert(corner_normal.end(), polygon_normals.begin(), polygon_normals.end());
    } else if (key == "p") {
      ++points_lines;
    } else if (key == "l") {
      ++line_lines;
    } else {
      ++ignored[std::string(key.substr(0, 40))];
    }
  }
  const std::size_t n = v.size() / 3;
  if (n == 0)
    throw_read_error(path, "", "the file defines no vertex ('v' line); the point cloud is empty");
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw_read_error(path, "", "more than 2^32 - 1 vertices");

  PointCloud cloud;
  const auto rows = static_cast<Eigen::Index>(n);
  cloud.positions = Eigen::Map<const Positions>(v.data(), rows, 3);

  // Normals: OBJ gives them per face corner. They become per-vertex normals
  // when every corner of a vertex names the same normal vector; a vertex with
  // two different ones (a crease, a seam) cannot hold both, and then all of
  // them are left out (and re-derived from the faces by the pipeline). A file
  // without faces pairs the i-th "vn" with the i-th "v".
  const std::size_t normal_count = vn.size() / 3;
  bool corners_have_normals = false;
  for (const std::int64_t ni : corner_normal) corners_have_normals |= ni >= 0;
  if (corners_have_normals) {
    std::vector<std::int64_t> of_vertex(n, -1);
    std::size_t conflicts = 0, missing = 0;
    for (std::size_t c = 0; c < corner_normal.size(); ++c) {
      const std::int64_t ni = corner_normal[c];
      std::int64_t& mine = of_vertex[faces.indices[c]];
      if (ni < 0) continue;
      if (mine < 0)
        mine = ni;
      else if (mine != ni && std::memcmp(&vn[3 * mine], &vn[3 * ni], 3 * sizeof(double)) != 0)
        ++conflicts;
    }
    for (const std::int64_t ni : of_vertex) missing += ni < 0;
    if (conflicts > 0 || missing > 0) {
      report.notices.push_back(
          "the OBJ normals are left out: " +
          (conflicts > 0 ? std::to_string(conflicts) +
                               " face corners give their vertex a second, different normal"
                         : std::to_string(missing) + " vertices have no normal") +
          "; normals are derived from the faces instead");
    } else {
      cloud.normals.resize(rows, 3);
      for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d)
          cloud.normals(static_cast<Eigen::Index>(i), d) = vn[3 * of_vertex[i] + d];
    }
  } else if (normal_count == n && faces.size() == 0) {
    cloud.normals = Eigen::Map<const Normals>(vn.data(), rows, 3);
  } else if (normal_count > 0) {
    report.notices.push_back("ignored " + std::to_string(normal_count) +
                             " 'vn' normals that no face corner uses");
  }

  if (colored == n) {
    // Float32 when every colour fits it (the usual 0-1 or 0-255), else
    // Float64: a colour beyond float's range would become inf and the file
    // written from it could not be read back (found by fuzz_read_obj).
    bool fits_float = true;
    for (const double c : colors)
      fits_float = fits_float && std::abs(c) <= std::numeric_limits<float>::max();
    const ScalarType type = fits_float ? ScalarType::Float32 : ScalarType::Float64;
    for (int d = 0; d < 3; ++d) {
      PointProperty p{d == 0 ? "red" : d == 1 ? "green" : "blue", type, {}};
      p.values.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        p.values[i] = fits_float ? static_cast<float>(colors[3 * i + d]) : colors[3 * i + d];
      cloud.extras.push_back(std::move(p));
    }
  } else if (colored > 0) {
    report.notices.push_back("ignored the colours of " + std::to_string(colored) + " of the " +
                             std::to_string(n) + " vertices (only some vertices have one)");
  }
  if (faces.size() > 0) set_face_list(cloud, faces);
  if (texcoords > 0)
    report.notices.push_back("ignored " + std::to_string(texcoords) +
                             " texture coordinates ('vt'); they are not written back");
  if (points_lines + line_lines > 0)
    report.notices.push_back("ignored " + std::to_string(points_lines + line_lines) +
                             " point and line elements ('p', 'l'); only faces are kept");
  std::string others;
  for (const auto& [key, count] : ignored)
    others += (others.empty() ? "" : ", ") + quoted(key) + " (" + std::to_string(count) + ")";
  if (!others.empty())
    report.notices.push_back("ignored the OBJ statements " + others +
                             " (groups, materials, smoothing groups, ...); they are not written "
                             "back");
  return cloud;
}

}  // namespace detexture::io_detail
