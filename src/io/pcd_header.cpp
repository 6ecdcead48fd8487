#include "pcd_header.h"

#include <cstring>
#include <string>
#include <vector>

#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {

char pcd_type_letter(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::Int16:
    case ScalarType::Int32:
      return 'I';
    case ScalarType::UInt8:
    case ScalarType::UInt16:
    case ScalarType::UInt32:
      return 'U';
    case ScalarType::Float32:
    case ScalarType::Float64:
      return 'F';
  }
  return '?';
}

namespace {

bool scalar_type(char letter, std::uint64_t size, ScalarType* type) {
  const ScalarType table[3][4] = {
      {ScalarType::Int8, ScalarType::Int16, ScalarType::Int32, ScalarType::Int32},
      {ScalarType::UInt8, ScalarType::UInt16, ScalarType::UInt32, ScalarType::UInt32},
      {ScalarType::Float32, ScalarType::Float32, ScalarType::Float32, ScalarType::Float64}};
  const int row = letter == 'I' ? 0 : letter == 'U' ? 1 : letter == 'F' ? 2 : -1;
  const int column = size == 1 ? 0 : size == 2 ? 1 : size == 4 ? 2 : size == 8 ? 3 : -1;
  if (row < 0 || column < 0) return false;
  if ((row == 2 && column < 2) || (row < 2 && column == 3)) return false;
  *type = table[row][column];
  return true;
}

}  // namespace

PcdHeader parse_pcd_header(std::string_view bytes, const std::string& path) {
  constexpr std::size_t kMaxHeaderBytes = std::size_t(1) << 20;
  PcdHeader header;
  TextLines lines(bytes.substr(0, std::min(bytes.size(), kMaxHeaderBytes)), 1);
  std::string_view line;
  std::vector<std::string_view> tokens;
  std::vector<std::string_view> names, sizes, types, counts;
  bool have_width = false, have_points = false, have_data = false;
  auto fail = [&](const std::string& what) { throw_read_error(path, at_line(lines.line()), what); };
  while (!have_data && lines.next(&line)) {
    if (std::memchr(line.data(), '\0', line.size()))
      fail("a NUL byte in the header; this is not a PCD file");
    if (!line.empty() && line[0] == '#') {
      header.comments.emplace_back(line.substr(
          line.find_first_not_of("# ") == std::string_view::npos ? line.size()
                                                                 : line.find_first_not_of("# ")));
      continue;
    }
    split_whitespace(line, &tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    std::vector<std::string_view> values(tokens.begin() + 1, tokens.end());
    auto one_count = [&](std::uint64_t* out) {
      if (values.size() != 1 || !parse_count(values[0], out))
        fail(std::string(key) + " must be followed by one non-negative integer");
    };
    if (key == "VERSION") {
      if (values.size() != 1 || (values[0] != "0.7" && values[0] != ".7"))
        fail("only PCD version 0.7 is supported, found " +
             (values.empty() ? std::string("none") : quoted(values[0])));
    } else if (key == "FIELDS" || key == "COLUMNS") {
      names = values;
    } else if (key == "SIZE") {
      sizes = values;
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "COUNT") {
      counts = values;
    } else if (key == "WIDTH") {
      one_count(&header.width);
      have_width = true;
    } else if (key == "HEIGHT") {
      one_count(&header.height);
    } else if (key == "POINTS") {
      one_count(&header.points);
      have_points = true;
    } else if (key == "VIEWPOINT") {
      if (values.size() != 7) fail("VIEWPOINT needs 7 numbers (tx ty tz qw qx qy qz)");
      for (int k = 0; k < 7; ++k)
        if (!parse_double(values[k], &header.viewpoint[k]))
          fail(quoted(values[k]) + " in VIEWPOINT is not a number");
    } else if (key == "DATA") {
      if (values.size() != 1) fail("DATA must be followed by ascii, binary or binary_compressed");
      if (values[0] == "ascii")
        header.data = PcdData::Ascii;
      else if (values[0] == "binary")
        header.data = PcdData::Binary;
      else if (values[0] == "binary_compressed")
        header.data = PcdData::BinaryCompressed;
      else
        fail("DATA " + quoted(values[0]) + "; expected ascii, binary or binary_compressed");
      have_data = true;
    } else {
      fail(lines.line() == 1 && key != "VERSION"
               ? "not a PCD file: the header starts with " + quoted(key)
               : "unknown header line " + quoted(key) + " in a PCD header");
    }
  }
  if (!have_data)
    throw_read_error(path, "",
                     bytes.size() > kMaxHeaderBytes
                         ? "no DATA line in the first MiB; this is not a PCD file"
                         : "the header has no DATA line; this is not a complete PCD file");
  header.data_offset = lines.position();
  header.data_line = lines.line() + 1;
  if (names.empty()) throw_read_error(path, "", "the header has no FIELDS line");
  if (sizes.size() != names.size() || types.size() != names.size() ||
      (!counts.empty() && counts.size() != names.size()))
    throw_read_error(path, "",
                     "FIELDS names " + std::to_string(names.size()) + " fields, but SIZE has " +
                         std::to_string(sizes.size()) + ", TYPE " + std::to_string(types.size()) +
                         " and COUNT " + std::to_string(counts.size()) + " entries");
  if (!have_width) throw_read_error(path, "", "the header has no WIDTH line");
  const std::uint64_t wh = header.width * header.height;
  if (header.height != 0 && wh / header.height != header.width)
    throw_read_error(path, "", "WIDTH times HEIGHT overflows");
  if (!have_points) header.points = wh;
  if (header.points != wh)
    throw_read_error(path, "",
                     "POINTS " + std::to_string(header.points) + " is not WIDTH " +
                         std::to_string(header.width) + " times HEIGHT " +
                         std::to_string(header.height));
  for (std::size_t k = 0; k < names.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j)
      if (names[j] == names[k] && names[k] != "_")
        throw_read_error(path, "", "two fields are named " + quoted(names[k]));
    for (const char c : names[k])
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
        throw_read_error(path, "",
                         "the field name " + quoted(names[k]) + " contains a control character");
    PcdField field;
    field.name = std::string(names[k]);
    std::uint64_t size = 0, count = 1;
    if (!parse_count(sizes[k], &size) || types[k].size() != 1 ||
        !scalar_type(types[k][0], size, &field.type))
      throw_read_error(path, "",
                       "field " + quoted(names[k]) + " has TYPE " + quoted(types[k]) +
                           " and SIZE " + quoted(sizes[k]) +
                           "; supported are I and U of size 1, 2, 4 and F of size 4, 8");
    if (!counts.empty() && (!parse_count(counts[k], &count) || count == 0 || count > 100000))
      throw_read_error(path, "",
                       "field " + quoted(names[k]) + " has COUNT " + quoted(counts[k]) +
                           "; expected 1 to 100000");
    field.count = static_cast<int>(count);
    field.offset = header.point_bytes;
    header.point_bytes += size * count;
    header.fields.push_back(field);
  }
  return header;
}

}  // namespace detexture::io_detail
