#include "read_pcd.h"

#include <lzf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io_text.h"
#include "pcd_header.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// Where each value of a point goes: a column of positions (0-2), of normals
// (3-5), an extra (kExtra + k), the packed colour (kColor) or nowhere (kSkip).
constexpr int kExtra = 16;
constexpr int kColor = 8;
constexpr int kSkip = -1;

struct Column {
  const PcdField* field;
  int item;  ///< 0 .. count-1
  int destination;
};

}  // namespace

PointCloud read_pcd(std::string_view bytes, const std::string& path, ReadReport& report) {
  const PcdHeader header = parse_pcd_header(bytes, path);
  auto find = [&](const char* name) -> const PcdField* {
    for (const PcdField& f : header.fields)
      if (f.name == name && f.count == 1) return &f;
    return nullptr;
  };
  for (const char* name : {"x", "y", "z"})
    if (!find(name))
      throw_read_error(path, "",
                       "the header has no field '" + std::string(name) +
                           "' (of COUNT 1); x, y and z are required");
  const bool has_normals = find("normal_x") && find("normal_y") && find("normal_z");
  const PcdField* color = find("rgba");
  const bool alpha = color != nullptr;
  if (!color) color = find("rgb");
  if (color && (color->type == ScalarType::Float64 || scalar_size(color->type) != 4))
    color = nullptr;
  // The names the extras would get; the colour is unpacked into red, green,
  // blue [alpha] only when no field takes those names (else it stays packed).
  std::vector<std::string> names;
  for (const PcdField& f : header.fields)
    for (int item = 0; item < f.count; ++item)
      if (f.name != "_")
        names.push_back(f.count == 1 ? f.name : f.name + "_" + std::to_string(item));
  for (const char* name : {"red", "green", "blue", "alpha"})
    if (std::find(names.begin(), names.end(), name) != names.end()) color = nullptr;
  {
    std::vector<std::string> sorted = names;
    std::sort(sorted.begin(), sorted.end());
    const auto twin = std::adjacent_find(sorted.begin(), sorted.end());
    if (twin != sorted.end())
      throw_read_error(path, "", "two fields or field items would both be named " + quoted(*twin));
  }

  PointCloud cloud;
  std::vector<Column> columns;
  const char* fixed[] = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
  for (const PcdField& f : header.fields) {
    for (int item = 0; item < f.count; ++item) {
      int d = kSkip;
      for (int k = 0; k < (has_normals ? 6 : 3); ++k)
        if (f.count == 1 && f.name == fixed[k]) d = k;
      if (&f == color) d = kColor;
      if (d == kSkip && f.name != "_") {
        d = kExtra + static_cast<int>(cloud.extras.size());
        cloud.extras.push_back(
            {f.count == 1 ? f.name : f.name + "_" + std::to_string(item), f.type, {}});
      }
      columns.push_back({&f, item, d});
    }
  }
  auto all_float = [&](int first) {
    for (int k = first; k < first + 3; ++k)
      if (find(fixed[k])->type != ScalarType::Float32) return false;
    return true;
  };
  if (all_float(0)) cloud.position_type = ScalarType::Float32;
  if (has_normals && all_float(3)) cloud.normal_type = ScalarType::Float32;

  const std::uint64_t n = header.points;
  if (n == 0) throw_read_error(path, "", "POINTS is 0; the point cloud is empty");
  const std::size_t left = bytes.size() - header.data_offset;
  // Bound the count by the data before allocating: ascii needs at least 2
  // bytes per value, binary point_bytes per point; compressed data is
  // checked against its declared sizes below.
  const std::uint64_t least_bytes =
      header.data == PcdData::Ascii ? 2 * columns.size() : header.point_bytes;
  if (header.data != PcdData::BinaryCompressed &&
      n > (left + 1) / std::max<std::uint64_t>(1, least_bytes))
    throw_read_error(path, at_byte(header.data_offset),
                     "POINTS declares " + std::to_string(n) + " points, but only " +
                         std::to_string(left) + " bytes of data follow the header");

  if (header.data == PcdData::BinaryCompressed && n > 0xffffffffull / header.point_bytes)
    throw_read_error(path, at_byte(header.data_offset),
                     "POINTS declares " + std::to_string(n) +
                         " points, more than binary_compressed data can hold (4 GiB)");
  std::vector<double> values(n * columns.size());  // row-major
  if (header.data == PcdData::Ascii) {
    TextLines lines(bytes.substr(header.data_offset), header.data_line);
    std::string_view line;
    std::vector<std::string_view> tokens;
    std::uint64_t i = 0;
    while (lines.next(&line)) {
      split_whitespace(line, &tokens);
      if (tokens.empty()) continue;
      if (i == n)
        throw_read_error(path, at_line(lines.line()),
                         "more points than the " + std::to_string(n) + " POINTS declares");
      if (tokens.size() != columns.size())
        throw_read_error(path, at_line(lines.line()),
                         std::to_string(tokens.size()) + " values; the fields call for " +
                             std::to_string(columns.size()));
      for (std::size_t c = 0; c < columns.size(); ++c) {
        double v = 0.0;
        const PcdField& f = *columns[c].field;
        // A packed colour: its bits. PCL reads (and writes) a TYPE F one as
        // the text of the float those bits make, a TYPE U one as an integer.
        if (columns[c].destination == kColor) {
          std::uint64_t bits = 0;
          float packed = 0.0f;
          if (f.type == ScalarType::Float32 && parse_double(tokens[c], &v)) {
            packed = static_cast<float>(v);
            std::uint32_t b = 0;
            std::memcpy(&b, &packed, 4);
            v = b;
          } else if (f.type != ScalarType::Float32 && parse_count(tokens[c], &bits) &&
                     bits <= 0xffffffffu) {
            v = static_cast<double>(bits);
          } else {
            throw_read_error(
                path, at_line(lines.line()),
                quoted(tokens[c]) + " is not a packed colour (field " + quoted(f.name) + ")");
          }
        } else if (parse_scalar(tokens[c], f.type, &v) != ParseResult::Ok) {
          throw_read_error(path, at_line(lines.line()),
                           quoted(tokens[c]) + " is not a valid " + ply_type_name(f.type) +
                               " (field " + quoted(f.name) + ")");
        }
        values[i * columns.size() + c] = v;
      }
      ++i;
    }
    if (i != n)
      throw_read_error(path, at_line(lines.line() + 1),
                       "the file ends after " + std::to_string(i) + " of the " + std::to_string(n) +
                           " points POINTS declares");
  } else {
    std::vector<unsigned char> decompressed;
    const unsigned char* data =
        reinterpret_cast<const unsigned char*>(bytes.data()) + header.data_offset;
    std::size_t data_bytes = left;
    if (header.data == PcdData::BinaryCompressed) {
      if (left < 8)
        throw_read_error(path, at_byte(header.data_offset),
                         "truncated binary_compressed data: no sizes after the header");
      const std::uint32_t packed = load_bytes<std::uint32_t>(data, !host_is_little_endian());
      const std::uint32_t unpacked = load_bytes<std::uint32_t>(data + 4, !host_is_little_endian());
      if (packed > left - 8)
        throw_read_error(path, at_byte(header.data_offset),
                         "truncated binary_compressed data: " + std::to_string(packed) +
                             " compressed bytes declared, " + std::to_string(left - 8) + " follow");
      if (unpacked != n * header.point_bytes)
        throw_read_error(path, at_byte(header.data_offset + 4),
                         "the uncompressed size " + std::to_string(unpacked) + " is not POINTS " +
                             std::to_string(n) + " times the " +
                             std::to_string(header.point_bytes) + " bytes of a point");
      // LZF expands at most about 132-fold (a 2-byte back reference copies up
      // to 264 bytes), so a larger claim is refused before allocating it.
      if (unpacked / 133 > packed)
        throw_read_error(path, at_byte(header.data_offset + 4),
                         "the uncompressed size " + std::to_string(unpacked) +
                             " is impossible for " + std::to_string(packed) + " LZF bytes");
      decompressed.resize(unpacked);
      if (unpacked > 0 &&
          lzf_decompress(data + 8, packed, decompressed.data(), unpacked) != unpacked)
        throw_read_error(path, at_byte(header.data_offset + 8),
                         "the LZF compressed data is corrupt (it does not decompress to " +
                             std::to_string(unpacked) + " bytes)");
      data = decompressed.data();
      data_bytes = decompressed.size();
    }
    if (n * header.point_bytes > data_bytes)
      throw_read_error(path, at_byte(header.data_offset),
                       "truncated binary data: " + std::to_string(n) + " points of " +
                           std::to_string(header.point_bytes) + " bytes need " +
                           std::to_string(n * header.point_bytes) + " bytes, the file has " +
                           std::to_string(data_bytes));
    const bool swap = !host_is_little_endian();
    const bool columns_first = header.data == PcdData::BinaryCompressed;
    for (std::uint64_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const PcdField& f = *columns[c].field;
        const std::size_t size = scalar_size(f.type);
        // binary: point after point; binary_compressed: field after field.
        const std::size_t at = columns_first
                                   ? f.offset * n + (i * f.count + columns[c].item) * size
                                   : i * header.point_bytes + f.offset + columns[c].item * size;
        values[i * columns.size() + c] =
            columns[c].destination == kColor
                ? static_cast<double>(load_bytes<std::uint32_t>(data + at, swap))
                : decode_scalar(data + at, f.type, swap);
      }
    if (!columns_first && data_bytes > n * header.point_bytes) {
      bool zeros = true;
      for (std::size_t k = n * header.point_bytes; k < data_bytes && zeros; ++k)
        zeros = data[k] == 0;
      if (!zeros)  // PCL pads its binary files with zeros to a page: not worth a notice
        report.notices.push_back("ignored " + std::to_string(data_bytes - n * header.point_bytes) +
                                 " bytes after the last point");
    }
  }

  // Points with a NaN coordinate are PCL's "no return" in organized clouds:
  // they carry nothing to filter, and PCD has no faces whose numbering they
  // would break, so they are dropped (and counted), unlike in the other formats.
  std::vector<std::uint64_t> kept;
  kept.reserve(n);
  for (std::uint64_t i = 0; i < n; ++i) {
    bool finite = true;
    for (std::size_t c = 0; c < columns.size(); ++c)
      if (columns[c].destination >= 0 && columns[c].destination < 3)
        finite = finite && std::isfinite(values[i * columns.size() + c]);
    if (finite) kept.push_back(i);
  }
  if (kept.empty())
    throw_read_error(path, "", "every point has a NaN or infinite coordinate; the cloud is empty");
  if (kept.size() < n)
    report.notices.push_back("dropped " + std::to_string(n - kept.size()) +
                             " points with NaN or infinite coordinates (PCL's invalid points); "
                             "the output holds " +
                             std::to_string(kept.size()) + " points, unorganized (HEIGHT 1)");
  const auto m = static_cast<Eigen::Index>(kept.size());
  cloud.positions.resize(m, 3);
  if (has_normals) cloud.normals.resize(m, 3);
  for (PointProperty& extra : cloud.extras) extra.values.resize(kept.size());
  std::vector<double> red, green, blue, alphas;
  if (color) {
    red.resize(kept.size()), green.resize(kept.size()), blue.resize(kept.size());
    if (alpha) alphas.resize(kept.size());
  }
  for (std::size_t r = 0; r < kept.size(); ++r) {
    const double* row = values.data() + kept[r] * columns.size();
    const auto i = static_cast<Eigen::Index>(r);
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const int d = columns[c].destination;
      if (d < 0) continue;
      if (d < 3)
        cloud.positions(i, d) = row[c];
      else if (d < 6)
        cloud.normals(i, d - 3) = row[c];
      else if (d == kColor) {
        const auto bits = static_cast<std::uint32_t>(row[c]);
        red[r] = (bits >> 16) & 255, green[r] = (bits >> 8) & 255, blue[r] = bits & 255;
        if (alpha) alphas[r] = bits >> 24;
      } else {
        cloud.extras[d - kExtra].values[r] = row[c];
      }
    }
  }
  if (color) {
    cloud.extras.push_back({"red", ScalarType::UInt8, std::move(red)});
    cloud.extras.push_back({"green", ScalarType::UInt8, std::move(green)});
    cloud.extras.push_back({"blue", ScalarType::UInt8, std::move(blue)});
    if (alpha) cloud.extras.push_back({"alpha", ScalarType::UInt8, std::move(alphas)});
  }
  for (const std::string& comment : header.comments)
    if (comment.rfind(".PCD", 0) != 0) cloud.comments.push_back(comment);
  const double* vp = header.viewpoint;
  if (vp[0] != 0 || vp[1] != 0 || vp[2] != 0 || vp[3] != 1 || vp[4] != 0 || vp[5] != 0 ||
      vp[6] != 0)
    report.notices.push_back(
        "the VIEWPOINT of the file is not written back (outputs get the "
        "identity)");
  return cloud;
}

}  // namespace detexture::io_detail
