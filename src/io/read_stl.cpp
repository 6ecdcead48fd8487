#include "read_stl.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "detexture/io/face_list.h"
#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// Welds triangle corners by exact position: the first corner at a position
// becomes the vertex, later ones reuse it. -0.0 and 0.0 are one position.
class Welder {
 public:
  std::uint32_t vertex(const double p[3]) {
    Key key{};
    for (int d = 0; d < 3; ++d) {
      const double x = p[d] == 0.0 ? 0.0 : p[d];
      std::memcpy(&key[d], &x, sizeof x);
    }
    const auto [it, added] = index_.try_emplace(key, static_cast<std::uint32_t>(index_.size()));
    if (added) positions_.insert(positions_.end(), p, p + 3);
    return it->second;
  }
  const std::vector<double>& positions() const { return positions_; }

 private:
  using Key = std::array<std::uint64_t, 3>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (std::uint64_t x : k) h = (h ^ x) * 1099511628211ull, h ^= h >> 29;
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Key, std::uint32_t, Hash> index_;
  std::vector<double> positions_;
};

PointCloud finish(const Welder& welder, const FaceList& faces, std::size_t degenerate,
                  ScalarType position_type, ReadReport& report) {
  PointCloud cloud;
  const auto n = static_cast<Eigen::Index>(welder.positions().size() / 3);
  cloud.positions = Eigen::Map<const Positions>(welder.positions().data(), n, 3);
  cloud.position_type = position_type;
  set_face_list(cloud, faces);
  if (degenerate > 0)
    report.notices.push_back(std::to_string(degenerate) +
                             " triangles have two corners at the same position; they are kept");
  return cloud;
}

PointCloud read_binary(std::string_view bytes, const std::string& path, std::uint32_t count,
                       ReadReport& report) {
  const bool swap = !host_is_little_endian();
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  Welder welder;
  FaceList faces;
  faces.offsets.reserve(std::size_t(count) + 1);
  faces.indices.reserve(3 * std::size_t(count));
  std::size_t degenerate = 0;
  for (std::uint32_t t = 0; t < count; ++t) {
    const unsigned char* facet = data + 84 + 50 * std::size_t(t);
    std::uint32_t corner[3];
    for (int c = 0; c < 3; ++c) {
      double p[3];
      for (int d = 0; d < 3; ++d) p[d] = load_bytes<float>(facet + 12 + 12 * c + 4 * d, swap);
      if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
        throw_read_error(path, at_byte(84 + 50 * std::size_t(t) + 12 + 12 * c),
                         "triangle " + std::to_string(t) +
                             " has a NaN or infinite corner; such points are refused");
      corner[c] = welder.vertex(p);
    }
    degenerate += corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2];
    faces.add(corner, 3);
  }
  return finish(welder, faces, degenerate, ScalarType::Float32, report);
}

PointCloud read_ascii(std::string_view bytes, const std::string& path, ReadReport& report) {
  TextLines lines(bytes, 1);
  std::string_view line;
  std::vector<std::string_view> tokens;
  Welder welder;
  FaceList faces;
  std::size_t degenerate = 0, solids = 0;
  enum class State { Outside, Solid, Facet, Loop } state = State::Outside;
  std::uint32_t corner[3];
  int corners = 0;
  auto fail = [&](const std::string& what) { throw_read_error(path, at_line(lines.line()), what); };
  auto expect = [&](const char* what) {
    fail("expected " + std::string(what) + ", found " + quoted(tokens[0]));
  };
  while (lines.next(&line)) {
    if (line.size() > kMaxTextLineBytes) fail("the line is too long for an STL file");
    if (std::memchr(line.data(), '\0', line.size()))
      fail("a NUL byte in an ascii STL file (a binary STL whose size does not match its count?)");
    split_whitespace(line, &tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    switch (state) {
      case State::Outside:
        if (key != "solid") expect("'solid'");
        state = State::Solid;
        ++solids;
        break;
      case State::Solid:
        if (key == "endsolid") {
          state = State::Outside;
        } else if (key == "facet") {
          if (tokens.size() != 5 || tokens[1] != "normal") fail("expected 'facet normal nx ny nz'");
          state = State::Facet;
        } else {
          expect("'facet normal' or 'endsolid'");
        }
        break;
      case State::Facet:
        if (key == "outer" && tokens.size() == 2 && tokens[1] == "loop") {
          state = State::Loop;
          corners = 0;
        } else if (key == "endfacet") {
          if (corners != 3)
            fail("a facet ends with " + std::to_string(corners) +
                 " corners; STL facets are triangles");
          faces.add(corner, 3);
          degenerate += corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2];
          state = State::Solid;
        } else {
          expect("'outer loop' or 'endfacet'");
        }
        break;
      case State::Loop:
        if (key == "vertex") {
          if (tokens.size() != 4) fail("expected 'vertex x y z'");
          if (corners == 3) fail("a facet with more than 3 vertices; STL facets are triangles");
          double p[3];
          for (int d = 0; d < 3; ++d)
            if (!parse_double(tokens[1 + d], &p[d]) || !std::isfinite(p[d]))
              fail(quoted(tokens[1 + d]) + " is not a finite number");
          corner[corners++] = welder.vertex(p);
        } else if (key == "endloop") {
          state = State::Facet;
        } else {
          expect("'vertex' or 'endloop'");
        }
        break;
    }
  }
  if (state != State::Outside && !(state == State::Solid && solids > 0))
    throw_read_error(path, at_line(lines.line()), "the file ends inside a facet");
  if (state == State::Solid) report.notices.push_back("the last solid has no 'endsolid' line");
  if (faces.size() == 0)
    throw_read_error(path, "", "the file holds no facet; the point cloud is empty");
  return finish(welder, faces, degenerate, ScalarType::Float64, report);
}

}  // namespace

PointCloud read_stl(std::string_view bytes, const std::string& path, ReadReport& report) {
  // A binary file is 84 + 50 n bytes for the n it declares at byte 80; that
  // test comes first, since binary files may start with "solid" too.
  if (bytes.size() >= 84) {
    const std::uint32_t count = load_bytes<std::uint32_t>(
        reinterpret_cast<const unsigned char*>(bytes.data()) + 80, !host_is_little_endian());
    if (bytes.size() == 84 + 50 * std::uint64_t(count)) {
      if (count == 0) throw_read_error(path, at_byte(80), "the file holds 0 triangles");
      return read_binary(bytes, path, count, report);
    }
  }
  std::size_t start = 0;
  while (start < bytes.size() && (is_blank(bytes[start]) || bytes[start] == '\n')) ++start;
  if (bytes.substr(start, 5) != "solid") {
    if (bytes.size() >= 84)
      throw_read_error(path, "",
                       "not an STL file: it does not start with 'solid', and as a binary STL its "
                       "size (" +
                           std::to_string(bytes.size()) + " bytes) does not match the " +
                           std::to_string(load_bytes<std::uint32_t>(
                               reinterpret_cast<const unsigned char*>(bytes.data()) + 80,
                               !host_is_little_endian())) +
                           " triangles declared at byte 80 (84 + 50 per triangle)");
    throw_read_error(path, "", "not an STL file: too short for a binary STL and no 'solid' line");
  }
  return read_ascii(bytes, path, report);
}

}  // namespace detexture::io_detail
