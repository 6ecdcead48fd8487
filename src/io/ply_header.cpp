#include "ply_header.h"

#include <string>
#include <unordered_set>

#include "detexture/io/read_point_cloud.h"
#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {

bool scalar_type_from_name(std::string_view name, ScalarType* type) {
  struct Entry {
    const char* name;
    ScalarType type;
  };
  static const Entry kEntries[] = {
      {"char", ScalarType::Int8},      {"int8", ScalarType::Int8},
      {"uchar", ScalarType::UInt8},    {"uint8", ScalarType::UInt8},
      {"short", ScalarType::Int16},    {"int16", ScalarType::Int16},
      {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},
      {"int", ScalarType::Int32},      {"int32", ScalarType::Int32},
      {"uint", ScalarType::UInt32},    {"uint32", ScalarType::UInt32},
      {"float", ScalarType::Float32},  {"float32", ScalarType::Float32},
      {"double", ScalarType::Float64}, {"float64", ScalarType::Float64},
  };
  for (const Entry& e : kEntries) {
    if (name == e.name) {
      *type = e.type;
      return true;
    }
  }
  return false;
}

namespace {

// The text after the keyword and one separating blank, kept verbatim.
std::string text_after_keyword(std::string_view line, std::string_view keyword) {
  std::size_t i = line.find(keyword) + keyword.size();
  if (i < line.size() && is_blank(line[i])) ++i;
  return std::string(line.substr(i < line.size() ? i : line.size()));
}

[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw_read_error(path, at_line(line), what);
}

// Names with control characters could not be written back (the writer
// refuses them, as other readers would choke on them): found by fuzzing.
void check_name(std::string_view name, const std::string& path, std::size_t line) {
  for (const char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      fail(path, line, "the name " + quoted(name) + " contains a control character");
}

// The last element declared, when it has no properties: one of no rows is
// dropped with a notice (PCL writes "element face 0" and nothing else for a
// cloud), one with rows is an error, since its rows could not be read.
void drop_empty_element(PlyHeader& header, const std::string& path) {
  if (header.elements.empty() || !header.elements.back().properties.empty()) return;
  const PlyElement& element = header.elements.back();
  if (element.count != 0)
    fail(path, element.line, "element " + quoted(element.name) + " has no properties");
  header.notices.push_back("ignored element " + quoted(element.name) +
                           ", which has no properties and no rows");
  header.elements.pop_back();
}

}  // namespace

PlyHeader parse_ply_header(std::string_view bytes, const std::string& path) {
  TextLines lines(bytes, 1);
  std::string_view line;
  if (!lines.next(&line) || line.substr(0, 3) != "ply" ||
      line.find_first_not_of(" \t", 3) != std::string_view::npos)
    fail(path, 1, "not a PLY file: the first line must be 'ply'");

  PlyHeader header;
  bool have_format = false;
  std::vector<std::string_view> tokens;
  // Names seen so far, so that checking for duplicates stays linear in the
  // number of properties (a scan of the earlier ones took 12 s for 80k).
  std::unordered_set<std::string_view> element_names, property_names;
  while (lines.next(&line)) {
    const std::size_t n = lines.line();
    if (lines.position() > kMaxPlyHeaderBytes)
      fail(path, n,
           "the header is longer than " + std::to_string(kMaxPlyHeaderBytes >> 20) +
               " MiB without an 'end_header' line; this is not a PLY file the reader accepts");
    split_whitespace(line, &tokens);
    if (tokens.empty()) continue;
    const std::string_view keyword = tokens[0];
    if (keyword == "comment") {
      header.comments.push_back(text_after_keyword(line, "comment"));
    } else if (keyword == "obj_info") {
      header.comments.push_back("obj_info " + text_after_keyword(line, "obj_info"));
    } else if (keyword == "format") {
      if (have_format) fail(path, n, "a second 'format' line");
      if (tokens.size() != 3)
        fail(path, n,
             "the format line must read 'format <ascii|binary_little_endian|"
             "binary_big_endian> 1.0'");
      if (tokens[1] == "ascii")
        header.encoding = PlyEncoding::Ascii;
      else if (tokens[1] == "binary_little_endian")
        header.encoding = PlyEncoding::BinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        header.encoding = PlyEncoding::BinaryBigEndian;
      else
        fail(path, n,
             "unknown PLY format " + quoted(tokens[1]) +
                 "; expected ascii, binary_little_endian or binary_big_endian");
      if (tokens[2] != "1.0" && tokens[2] != "1")
        fail(path, n, "unsupported PLY version " + quoted(tokens[2]) + "; only 1.0 is supported");
      have_format = true;
    } else if (keyword == "element") {
      if (tokens.size() != 3) fail(path, n, "an element line must read 'element <name> <count>'");
      if (!have_format) fail(path, n, "the 'format' line must come before the first element");
      drop_empty_element(header, path);
      check_name(tokens[1], path, n);
      PlyElement element;
      element.name = std::string(tokens[1]);
      element.line = n;
      if (!parse_count(tokens[2], &element.count))
        fail(path, n,
             "the count " + quoted(tokens[2]) + " of element " + quoted(tokens[1]) +
                 " is not a non-negative integer");
      if (!element_names.insert(tokens[1]).second)
        fail(path, n, "element " + quoted(tokens[1]) + " declared twice");
      property_names.clear();
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail(path, n, "a property before any element");
      PlyElement& element = header.elements.back();
      PlyProperty property;
      const bool is_list = tokens.size() >= 2 && tokens[1] == "list";
      if (is_list ? tokens.size() != 5 : tokens.size() != 3)
        fail(path, n,
             "a property line must read 'property <type> <name>' or "
             "'property list <count type> <item type> <name>'");
      property.is_list = is_list;
      const std::string_view type_name = is_list ? tokens[3] : tokens[1];
      if (!scalar_type_from_name(type_name, &property.type))
        fail(path, n,
             "unknown property type " + quoted(type_name) +
                 "; expected char, uchar, short, ushort, int, uint, float, double or int8 ... "
                 "float64");
      if (is_list) {
        if (!scalar_type_from_name(tokens[2], &property.count_type))
          fail(path, n, "unknown list count type " + quoted(tokens[2]));
        if (!is_integer_type(property.count_type))
          fail(path, n,
               "the count type of a list must be an integer type, not " + quoted(tokens[2]));
      }
      check_name(tokens.back(), path, n);
      property.name = std::string(tokens.back());
      if (!property_names.insert(tokens.back()).second)
        fail(path, n,
             "property " + quoted(property.name) + " declared twice in element " +
                 quoted(element.name));
      element.properties.push_back(std::move(property));
    } else if (keyword == "end_header") {
      if (tokens.size() != 1) fail(path, n, "unexpected text after 'end_header'");
      if (!have_format) fail(path, n, "the header has no 'format' line");
      drop_empty_element(header, path);
      header.data_offset = lines.position();
      header.data_line = n + 1;
      return header;
    } else if (header.elements.empty()) {
      // Old Blender versions write a bare "Created by Blender3D 247 - ..."
      // line; assimp, MeshLab and CloudCompare read such files. Before the
      // first element no line can change how the data is read, so an
      // unknown one is kept as a comment; after it, it might have been a
      // misspelled property, which would shift every column.
      header.comments.push_back(std::string(line));
      header.notices.push_back("line " + std::to_string(n) + " of the header, " +
                               quoted(line.substr(0, 60)) +
                               ", is not a PLY keyword line; it is kept as a comment");
    } else {
      fail(path, n,
           "unknown header keyword " + quoted(keyword) +
               "; expected comment, obj_info, format, element, property or end_header");
    }
  }
  fail(path, lines.line(), "the header has no 'end_header' line");
}

}  // namespace detexture::io_detail
