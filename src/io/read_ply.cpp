#include "read_ply.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io_text.h"
#include "ply_header.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

std::string row_context(const PlyElement& element, std::uint64_t row) {
  return "row " + std::to_string(row + 1) + " of " + std::to_string(element.count) +
         " of element " + quoted(element.name);
}

// Both row readers offer the same operations, so that one template walks the
// elements of an ascii or a binary file: begin_element, capacity, begin_row,
// value, check_list, end_row, finish, fail.

// Ascii data: one row per line (blank lines are skipped), values separated by
// blanks. Errors give the line.
class AsciiRows {
 public:
  AsciiRows(std::string_view bytes, const PlyHeader& header, const std::string& path)
      : lines_(bytes.substr(header.data_offset), header.data_line), path_(path) {}

  void begin_element(const PlyElement& element) { element_ = &element; }

  /// How many rows of element to allocate for. A complete row holds at least
  /// one token per property, each followed by a blank or a line break, so the
  /// remaining bytes bound the complete rows; one more may be started (and
  /// fail). A huge declared count thus fails with its line before it is
  /// ever allocated.
  std::uint64_t capacity(const PlyElement& element) const {
    const std::uint64_t min_row_bytes = 2 * element.properties.size();
    return std::min<std::uint64_t>(element.count, (lines_.bytes_left() + 1) / min_row_bytes + 1);
  }

  void begin_row(std::uint64_t row) {
    row_ = row;
    std::string_view line;
    do {
      if (!lines_.next(&line))
        throw_read_error(path_, at_line(lines_.line() + 1),
                         "the file ends after " + std::to_string(row) + " of the " +
                             std::to_string(element_->count) + " rows of element " +
                             quoted(element_->name) +
                             "; the header's count does not match the data");
      split_whitespace(line, &tokens_);
    } while (tokens_.empty());
    next_ = 0;
  }

  double value(const PlyProperty& property, ScalarType type) {
    if (next_ >= tokens_.size())
      fail("too few values for the " + std::to_string(element_->properties.size()) + " properties");
    const std::string_view token = tokens_[next_++];
    double v = 0.0;
    switch (parse_scalar(token, type, &v)) {
      case ParseResult::Ok:
        break;
      case ParseResult::NotANumber:
        fail(quoted(token) + " is not a valid " + ply_type_name(type) + " (property " +
             quoted(property.name) + ")");
      case ParseResult::OutOfRange:
        fail(quoted(token) + " is out of range for " + ply_type_name(type) + " (property " +
             quoted(property.name) + ")");
    }
    return v;
  }

  void check_list(std::uint64_t count, const PlyProperty& property) {
    if (count > tokens_.size() - next_)
      fail("list property " + quoted(property.name) + " declares " + std::to_string(count) +
           " items, but only " + std::to_string(tokens_.size() - next_) + " values follow");
  }

  void end_row() {
    if (next_ < tokens_.size())
      fail(std::to_string(tokens_.size()) + " values, more than the " +
           std::to_string(element_->properties.size()) + " properties call for");
  }

  void finish(ReadReport&) {
    std::string_view line;
    while (lines_.next(&line)) {
      split_whitespace(line, &tokens_);
      if (!tokens_.empty())
        throw_read_error(path_, at_line(lines_.line()),
                         "unexpected data after the last row of element " + quoted(element_->name) +
                             "; the header's count does not match the data");
    }
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw_read_error(path_, at_line(lines_.line()), what + " in " + row_context(*element_, row_));
  }

 private:
  TextLines lines_;
  const std::string& path_;
  const PlyElement* element_ = nullptr;
  std::uint64_t row_ = 0;
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
};

// Binary data, either byte order. Errors give the byte offset.
class BinaryRows {
 public:
  BinaryRows(std::string_view bytes, const PlyHeader& header, const std::string& path)
      : data_(reinterpret_cast<const unsigned char*>(bytes.data())),
        pos_(header.data_offset),
        end_(bytes.size()),
        swap_((header.encoding == PlyEncoding::BinaryLittleEndian) != host_is_little_endian()),
        path_(path) {}

  void begin_element(const PlyElement& element) {
    element_ = &element;
    std::uint64_t min_row_bytes = 0;
    for (const PlyProperty& p : element.properties)
      min_row_bytes += scalar_size(p.is_list ? p.count_type : p.type);
    if (element.count > (end_ - pos_) / min_row_bytes)
      throw_read_error(path_, at_byte(pos_),
                       "truncated binary data: element " + quoted(element.name) + " declares " +
                           std::to_string(element.count) + " rows of " +
                           (min_row_bytes == row_bytes(element) ? "" : "at least ") +
                           std::to_string(min_row_bytes) + " bytes, but the file ends at byte " +
                           std::to_string(end_));
  }

  /// begin_element checked that the file holds every row.
  std::uint64_t capacity(const PlyElement& element) const { return element.count; }

  void begin_row(std::uint64_t row) {
    row_ = row;
    row_start_ = pos_;
  }

  double value(const PlyProperty& property, ScalarType type) {
    const std::size_t size = scalar_size(type);
    if (end_ - pos_ < size)
      throw_read_error(path_, at_byte(pos_),
                       "truncated binary data: the file ends inside property " +
                           quoted(property.name) + " of " + row_context(*element_, row_));
    const double v = decode_scalar(data_ + pos_, type, swap_);
    pos_ += size;
    return v;
  }

  void check_list(std::uint64_t count, const PlyProperty& property) {
    if (count > (end_ - pos_) / scalar_size(property.type))
      throw_read_error(path_, at_byte(pos_),
                       "truncated binary data: list property " + quoted(property.name) + " of " +
                           row_context(*element_, row_) + " declares " + std::to_string(count) +
                           " items, but the file ends at byte " + std::to_string(end_));
  }

  void end_row() {}

  void finish(ReadReport& report) {
    if (pos_ < end_)
      report.notices.push_back("ignored " + std::to_string(end_ - pos_) +
                               " bytes after the last element, from byte " + std::to_string(pos_));
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw_read_error(path_, at_byte(row_start_), what + " in " + row_context(*element_, row_));
  }

 private:
  static std::uint64_t row_bytes(const PlyElement& element) {
    std::uint64_t bytes = 0;
    for (const PlyProperty& p : element.properties) {
      if (p.is_list) return 0;
      bytes += scalar_size(p.type);
    }
    return bytes;
  }

  const unsigned char* data_;
  std::size_t pos_;
  std::size_t end_;
  bool swap_;
  const std::string& path_;
  const PlyElement* element_ = nullptr;
  std::uint64_t row_ = 0;
  std::size_t row_start_ = 0;
};

template <class Rows>
std::uint64_t read_list_count(Rows& rows, const PlyProperty& property) {
  const double count = rows.value(property, property.count_type);
  if (count < 0) rows.fail("list property " + quoted(property.name) + " has a negative count");
  rows.check_list(static_cast<std::uint64_t>(count), property);
  return static_cast<std::uint64_t>(count);
}

// Where each vertex property goes: 0-2 positions, 3-5 normals, kExtra + k
// extras[k], kSkip for list properties (which PointProperty cannot hold).
constexpr int kExtra = 6;
constexpr int kSkip = -1;

struct VertexLayout {
  std::vector<int> destination;  ///< one per property of the vertex element
  bool has_normals = false;
  std::vector<PointProperty> extras;  ///< names and types, no values yet
};

VertexLayout vertex_layout(const PlyElement& vertex, const std::string& path, ReadReport& report) {
  auto find = [&](const char* name) -> const PlyProperty* {
    for (const PlyProperty& p : vertex.properties)
      if (p.name == name) return &p;
    return nullptr;
  };
  for (const char* name : {"x", "y", "z"}) {
    const PlyProperty* p = find(name);
    if (!p)
      throw_read_error(
          path, at_line(vertex.line),
          "element 'vertex' has no property '" + std::string(name) + "'; x, y and z are required");
    if (p->is_list)
      throw_read_error(path, at_line(vertex.line),
                       "property '" + std::string(name) +
                           "' of element 'vertex' is a list; a coordinate must be a scalar");
  }
  const char* normal_names[] = {"nx", "ny", "nz"};
  int scalar_normals = 0;
  for (const char* name : normal_names) {
    const PlyProperty* p = find(name);
    scalar_normals += p && !p->is_list;
  }
  VertexLayout layout;
  layout.has_normals = scalar_normals == 3;
  if (scalar_normals > 0 && !layout.has_normals)
    report.notices.push_back(
        "element 'vertex' has only some of nx, ny, nz; they are kept as "
        "extra properties, not as normals");
  const char* fixed[] = {"x", "y", "z", "nx", "ny", "nz"};
  for (const PlyProperty& p : vertex.properties) {
    if (p.is_list) {
      layout.destination.push_back(kSkip);
      report.notices.push_back("skipped list property " + quoted(p.name) +
                               " of element 'vertex'; it will not be written back");
      continue;
    }
    int d = -1;
    for (int k = 0; k < (layout.has_normals ? 6 : 3); ++k)
      if (p.name == fixed[k]) d = k;
    if (d < 0) {
      d = kExtra + static_cast<int>(layout.extras.size());
      layout.extras.push_back({p.name, p.type, {}});
    }
    layout.destination.push_back(d);
  }
  return layout;
}

template <class Rows>
void read_vertices(Rows& rows, const PlyElement& vertex, VertexLayout& layout, PointCloud& cloud) {
  rows.begin_element(vertex);
  const std::uint64_t capacity = rows.capacity(vertex);
  const auto n = static_cast<Eigen::Index>(capacity);
  cloud.positions.resize(n, 3);
  if (layout.has_normals) cloud.normals.resize(n, 3);
  for (PointProperty& extra : layout.extras) extra.values.resize(capacity);
  for (std::uint64_t row = 0; row < vertex.count; ++row) {
    rows.begin_row(row);
    if (row >= capacity) rows.fail("more rows than the data can hold");
    const auto i = static_cast<Eigen::Index>(row);
    for (std::size_t k = 0; k < vertex.properties.size(); ++k) {
      const PlyProperty& p = vertex.properties[k];
      const int d = layout.destination[k];
      if (d == kSkip) {
        const std::uint64_t count = read_list_count(rows, p);
        for (std::uint64_t j = 0; j < count; ++j) rows.value(p, p.type);
        continue;
      }
      const double v = rows.value(p, p.type);
      if (d < 3)
        cloud.positions(i, d) = v;
      else if (d < kExtra)
        cloud.normals(i, d - 3) = v;
      else
        layout.extras[d - kExtra].values[row] = v;
    }
    rows.end_row();
    if (!cloud.positions.row(i).allFinite())
      rows.fail(
          "a NaN or infinite coordinate; such points are refused, not dropped, since "
          "dropping them would break the numbering of the vertices");
  }
  cloud.extras = std::move(layout.extras);
}

template <class Rows>
OtherElement read_other_element(Rows& rows, const PlyElement& element) {
  rows.begin_element(element);
  OtherElement out;
  out.name = element.name;
  for (const PlyProperty& p : element.properties)
    out.properties.push_back({p.name, p.type, p.is_list, p.count_type});
  out.row_offsets.reserve(rows.capacity(element) + 1);
  out.row_offsets.push_back(0);
  for (std::uint64_t row = 0; row < element.count; ++row) {
    rows.begin_row(row);
    for (const PlyProperty& p : element.properties) {
      if (p.is_list) {
        const std::uint64_t count = read_list_count(rows, p);
        out.values.push_back(static_cast<double>(count));
        for (std::uint64_t j = 0; j < count; ++j) out.values.push_back(rows.value(p, p.type));
      } else {
        out.values.push_back(rows.value(p, p.type));
      }
    }
    rows.end_row();
    out.row_offsets.push_back(out.values.size());
  }
  return out;
}

template <class Rows>
void read_elements(Rows& rows, const PlyHeader& header, VertexLayout& layout, PointCloud& cloud,
                   ReadReport& report) {
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex")
      read_vertices(rows, element, layout, cloud);
    else
      cloud.other_elements.push_back(read_other_element(rows, element));
  }
  rows.finish(report);
}

}  // namespace

PointCloud read_ply(std::string_view bytes, const std::string& path, ReadReport& report) {
  const PlyHeader header = parse_ply_header(bytes, path);
  for (const std::string& notice : header.notices) report.notices.push_back(notice);
  const PlyElement* vertex = nullptr;
  for (const PlyElement& element : header.elements)
    if (element.name == "vertex") vertex = &element;
  if (!vertex)
    throw_read_error(path, at_line(header.data_line - 1),
                     "the header declares no 'vertex' element");
  if (vertex->count == 0)
    throw_read_error(path, at_line(vertex->line),
                     "element 'vertex' has 0 rows; the point cloud is empty");
  VertexLayout layout = vertex_layout(*vertex, path, report);

  PointCloud cloud;
  cloud.comments = header.comments;
  // Keep single precision when the file had it for all three components, so
  // output files do not double; one double component (float x, double y z)
  // makes all three double, so that no value is narrowed.
  auto all_float = [&](std::initializer_list<const char*> names) {
    int found = 0;
    for (const PlyProperty& p : vertex->properties)
      for (const char* name : names)
        if (p.name == name) {
          if (p.is_list || p.type != ScalarType::Float32) return false;
          ++found;
        }
    return found == 3;
  };
  if (all_float({"x", "y", "z"})) cloud.position_type = ScalarType::Float32;
  if (layout.has_normals && all_float({"nx", "ny", "nz"})) cloud.normal_type = ScalarType::Float32;
  if (header.encoding == PlyEncoding::Ascii) {
    AsciiRows rows(bytes, header, path);
    read_elements(rows, header, layout, cloud, report);
  } else {
    BinaryRows rows(bytes, header, path);
    read_elements(rows, header, layout, cloud, report);
  }
  return cloud;
}

}  // namespace detexture::io_detail
