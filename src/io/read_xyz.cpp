#include "read_xyz.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// Split a line into fields separated by blanks or by one comma (with blanks
// around it). Returns the offending position's description, or "" when fine:
// an empty field ("1,,2", a leading or trailing comma) is an error, since
// silently closing the gap would shift the columns.
std::string split_fields(std::string_view line, std::vector<std::string_view>* fields) {
  fields->clear();
  std::size_t i = 0;
  auto skip_blanks = [&] {
    while (i < line.size() && is_blank(line[i])) ++i;
  };
  skip_blanks();
  if (i < line.size() && line[i] == ',') return "an empty field before the first comma";
  while (i < line.size()) {
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i]) && line[i] != ',') ++i;
    fields->push_back(line.substr(start, i - start));
    skip_blanks();
    if (i < line.size() && line[i] == ',') {
      ++i;
      skip_blanks();
      if (i == line.size() || line[i] == ',')
        return "an empty field after comma " + std::to_string(fields->size());
    }
  }
  return "";
}

}  // namespace

PointCloud read_xyz(std::string_view bytes, const std::string& path, ReadReport&) {
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);  // UTF-8 byte order mark
  TextLines lines(bytes, 1);
  std::string_view line;
  std::vector<std::string_view> fields;
  std::vector<double> values;  // row-major, columns per row
  std::size_t columns = 0, first_row_line = 0;
  std::uint64_t declared = 0;
  std::size_t declared_line = 0;
  while (lines.next(&line)) {
    if (line.size() > kMaxTextLineBytes)
      throw_read_error(path, at_line(lines.line()),
                       "the line is " + std::to_string(line.size()) + " bytes long, more than " +
                           std::to_string(kMaxTextLineBytes >> 20) +
                           " MiB; this is not a text point cloud the reader accepts");
    if (std::memchr(line.data(), '\0', line.size()))
      throw_read_error(path, at_line(lines.line()),
                       "a NUL byte; this is binary data, not a text point cloud");
    line = line.substr(0, line.find('#'));
    const std::string problem = split_fields(line, &fields);
    if (!problem.empty()) throw_read_error(path, at_line(lines.line()), problem);
    if (fields.empty()) continue;
    // A .pts file starts with the number of points on a line of its own.
    if (columns == 0 && declared_line == 0 && fields.size() == 1 &&
        parse_count(fields[0], &declared)) {
      declared_line = lines.line();
      continue;
    }
    if (columns == 0) {
      if (fields.size() != 3 && fields.size() < 6)
        throw_read_error(path, at_line(lines.line()),
                         std::to_string(fields.size()) +
                             " values; expected 3 (x y z) or at least 6 (x y z nx ny nz ...)");
      if (fields.size() > kMaxXyzColumns)
        throw_read_error(path, at_line(lines.line()),
                         std::to_string(fields.size()) + " values, more than the " +
                             std::to_string(kMaxXyzColumns) + " columns the reader accepts");
      columns = fields.size();
      first_row_line = lines.line();
    } else if (fields.size() != columns) {
      throw_read_error(path, at_line(lines.line()),
                       std::to_string(fields.size()) + " values, but the first row (line " +
                           std::to_string(first_row_line) + ") has " + std::to_string(columns) +
                           "; every row must have the same number of columns");
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = 0.0;
      if (!parse_double(fields[c], &v))
        throw_read_error(
            path, at_line(lines.line()),
            quoted(fields[c]) + " (column " + std::to_string(c + 1) + ") is not a number" +
                (first_row_line == lines.line() ? "; comment out header lines with '#'" : ""));
      if (c < 3 && !std::isfinite(v))
        throw_read_error(path, at_line(lines.line()),
                         "a NaN or infinite coordinate; such points are refused, not dropped");
      values.push_back(v);
    }
  }
  const std::size_t n = columns == 0 ? 0 : values.size() / columns;
  if (n == 0)
    throw_read_error(path, lines.line() == 0 ? "" : at_line(lines.line()),
                     "the file holds no point; the point cloud is empty");
  if (declared_line != 0 && declared != n)
    throw_read_error(path, at_line(declared_line),
                     "the count line declares " + std::to_string(declared) +
                         " points, but the file has " + std::to_string(n));

  PointCloud cloud;
  const auto rows = static_cast<Eigen::Index>(n);
  cloud.positions.resize(rows, 3);
  if (columns >= 6) cloud.normals.resize(rows, 3);
  for (std::size_t c = 6; c < columns; ++c)
    cloud.extras.push_back(
        {"field" + std::to_string(c), ScalarType::Float64, std::vector<double>(n)});
  for (std::size_t i = 0; i < n; ++i) {
    const double* row = values.data() + i * columns;
    const auto r = static_cast<Eigen::Index>(i);
    cloud.positions.row(r) << row[0], row[1], row[2];
    if (columns >= 6) cloud.normals.row(r) << row[3], row[4], row[5];
    for (std::size_t c = 6; c < columns; ++c) cloud.extras[c - 6].values[i] = row[c];
  }
  return cloud;
}

}  // namespace detexture::io_detail
