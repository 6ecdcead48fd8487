#include "read_off.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "detexture/io/face_list.h"
#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// The lines of an OFF file without comments ('#' to the end of the line)
// and blank lines, split into tokens.
class OffLines {
 public:
  OffLines(std::string_view bytes, const std::string& path) : lines_(bytes, 1), path_(path) {}

  bool next(std::vector<std::string_view>* tokens) {
    std::string_view line;
    while (lines_.next(&line)) {
      if (line.size() > kMaxTextLineBytes)
        fail("the line is longer than " + std::to_string(kMaxTextLineBytes >> 20) +
             " MiB; this is not an OFF file the reader accepts");
      if (std::memchr(line.data(), '\0', line.size()))
        fail("a NUL byte; this is binary data, not a text OFF file");
      split_whitespace(line.substr(0, line.find('#')), tokens);
      if (!tokens->empty()) return true;
    }
    return false;
  }
  std::size_t line() const { return lines_.line(); }
  std::size_t bytes_left() const { return lines_.bytes_left(); }
  [[noreturn]] void fail(const std::string& what) const {
    throw_read_error(path_, at_line(lines_.line()), what);
  }

 private:
  TextLines lines_;
  const std::string& path_;
};

}  // namespace

PointCloud read_off(std::string_view bytes, const std::string& path, ReadReport& report) {
  OffLines lines(bytes, path);
  std::vector<std::string_view> tokens;
  if (!lines.next(&tokens))
    throw_read_error(path, "", "the file is empty; an OFF file starts with 'OFF'");
  // [C][N]OFF, in either order of C and N; the counts may follow on the
  // same line.
  const std::string_view keyword = tokens[0];
  bool colors = false, normals = false;
  const std::size_t off_at = keyword.size() >= 3 ? keyword.size() - 3 : std::string_view::npos;
  bool valid = off_at != std::string_view::npos && keyword.substr(off_at) == "OFF";
  for (std::size_t k = 0; valid && k < off_at; ++k) {
    if (keyword[k] == 'C' && !colors)
      colors = true;
    else if (keyword[k] == 'N' && !normals)
      normals = true;
    else
      valid = false;
  }
  if (!valid)
    lines.fail("the first word is " + quoted(keyword) +
               "; expected OFF, COFF, NOFF or CNOFF (4OFF, nOFF, STOFF are not supported)");
  if (tokens.size() > 1 && tokens[1] == "BINARY") lines.fail("binary OFF is not supported");
  tokens.erase(tokens.begin());
  if (tokens.empty() && !lines.next(&tokens))
    lines.fail("the file ends before the counts line 'vertices faces edges'");
  if (tokens.size() != 2 && tokens.size() != 3)
    lines.fail("expected the counts 'vertices faces edges', found " +
               std::to_string(tokens.size()) + " values");
  std::uint64_t vertex_count = 0, face_count = 0;
  if (!parse_count(tokens[0], &vertex_count) || !parse_count(tokens[1], &face_count))
    lines.fail("the counts " + quoted(tokens[0]) + " " + quoted(tokens[1]) +
               " are not non-negative integers");
  if (vertex_count == 0) lines.fail("the file declares 0 vertices; the point cloud is empty");
  // Every vertex and face line holds at least "0 0 0\n"-like 2 bytes per
  // value: a count larger than the bytes left fails here, before allocating.
  // (Each count is bounded first, so that the sum cannot overflow.)
  const std::uint64_t left = lines.bytes_left() + 1;
  if (vertex_count > left / 6 || face_count > left / 4 ||
      6 * vertex_count + 4 * face_count > left ||
      vertex_count > std::numeric_limits<std::uint32_t>::max())
    lines.fail("the counts declare " + std::to_string(vertex_count) + " vertices and " +
               std::to_string(face_count) + " faces, more than the " +
               std::to_string(lines.bytes_left()) + " bytes left in the file can hold");
  const std::size_t columns = 3 + (normals ? 3 : 0);
  PointCloud cloud;
  const auto n = static_cast<Eigen::Index>(vertex_count);
  cloud.positions.resize(n, 3);
  if (normals) cloud.normals.resize(n, 3);
  std::vector<double> color_values;  // 4 per vertex
  std::size_t color_columns = 0;     // 3 or 4, from the first vertex
  bool color_integers = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!lines.next(&tokens))
      lines.fail("the file ends after " + std::to_string(i) + " of the " +
                 std::to_string(vertex_count) + " vertices");
    const std::size_t extra = tokens.size() - std::min(tokens.size(), columns);
    if (tokens.size() < columns || (!colors && extra > 0) || (colors && extra != 3 && extra != 4) ||
        (color_columns && extra != color_columns))
      lines.fail("vertex " + std::to_string(i) + " has " + std::to_string(tokens.size()) +
                 " values; expected x y z" + (normals ? " nx ny nz" : "") +
                 (colors ? " r g b [a]" : ""));
    if (colors) color_columns = extra;
    for (std::size_t k = 0; k < tokens.size(); ++k) {
      double x = 0.0;
      if (!parse_double(tokens[k], &x))
        lines.fail(quoted(tokens[k]) + " is not a number (vertex " + std::to_string(i) + ")");
      if (k < 3 && !std::isfinite(x))
        lines.fail("a NaN or infinite coordinate; such points are refused, not dropped");
      if (k < 3)
        cloud.positions(i, static_cast<int>(k)) = x;
      else if (k < columns)
        cloud.normals(i, static_cast<int>(k - 3)) = x;
      else {
        color_values.push_back(x);
        color_integers = color_integers && x == std::floor(x) && x >= 0 && x <= 255;
      }
    }
  }
  FaceList faces;
  faces.offsets.reserve(face_count + 1);
  std::vector<std::uint32_t> polygon;
  std::size_t face_colors = 0;
  for (std::uint64_t f = 0; f < face_count; ++f) {
    if (!lines.next(&tokens))
      lines.fail("the file ends after " + std::to_string(f) + " of the " +
                 std::to_string(face_count) + " faces");
    std::uint64_t corners = 0;
    if (!parse_count(tokens[0], &corners) || corners < 3)
      lines.fail("face " + std::to_string(f) + " starts with " + quoted(tokens[0]) +
                 "; expected its number of corners, at least 3");
    // corners >= size, not size < corners + 1: a count of 2^64 - 1 wraps.
    if (corners >= tokens.size())
      lines.fail("face " + std::to_string(f) + " declares " + std::to_string(corners) +
                 " corners, but only " + std::to_string(tokens.size() - 1) + " values follow");
    polygon.clear();
    for (std::uint64_t k = 1; k <= corners; ++k) {
      std::uint64_t index = 0;
      if (!parse_count(tokens[k], &index) || index >= vertex_count)
        lines.fail("face " + std::to_string(f) + " refers to vertex " + quoted(tokens[k]) +
                   ", but the file has " + std::to_string(vertex_count) + " vertices (0-based)");
      polygon.push_back(static_cast<std::uint32_t>(index));
    }
    face_colors += tokens.size() > corners + 1;
    faces.add(polygon.data(), polygon.size());
  }
  if (lines.next(&tokens))
    lines.fail("unexpected data after the last of the " + std::to_string(face_count) +
               " faces; the counts do not match the data");
  if (color_columns > 0) {
    const char* names[] = {"red", "green", "blue", "alpha"};
    for (std::size_t c = 0; c < color_columns; ++c) {
      PointProperty p{names[c], color_integers ? ScalarType::UInt8 : ScalarType::Float32, {}};
      p.values.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i)
        p.values[i] = color_values[i * color_columns + c];
      if (!color_integers)
        for (double& x : p.values) x = static_cast<float>(x);
      cloud.extras.push_back(std::move(p));
    }
  }
  if (face_colors > 0)
    report.notices.push_back("ignored the colours of " + std::to_string(face_colors) +
                             " faces; they are not written back");
  if (faces.size() > 0) set_face_list(cloud, faces);
  return cloud;
}

}  // namespace detexture::io_detail
