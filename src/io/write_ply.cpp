#include "write_ply.h"

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "io_text.h"
#include "scalar_codec.h"

namespace detexture::io_detail {
namespace {

// Writes one row's values in either encoding.
class RowWriter {
 public:
  RowWriter(OutputBuffer& out, PlyEncoding encoding)
      : out_(out),
        ascii_(encoding == PlyEncoding::Ascii),
        swap_((encoding == PlyEncoding::BinaryLittleEndian) != host_is_little_endian()) {}

  /// value must satisfy fits_scalar(value, type).
  void value(double value, ScalarType type) {
    if (ascii_) {
      if (!first_) out_.text() += ' ';
      append_scalar_text(out_.text(), value, type);
      first_ = false;
    } else {
      unsigned char bytes[8];
      encode_scalar(bytes, value, type, swap_);
      out_.append(bytes, scalar_size(type));
    }
  }

  void end_row() {
    if (ascii_) out_.text() += '\n';
    first_ = true;
    out_.maybe_flush();
  }

 private:
  OutputBuffer& out_;
  bool ascii_;
  bool swap_;
  bool first_ = true;
};

bool is_valid_name(const std::string& name) {
  if (name.empty()) return false;
  for (const char c : name)
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f) return false;
  return true;
}

void check_names(const PointCloud& cloud, const std::string& path) {
  // Sets, so that a cloud with 200k properties is checked in linear time.
  std::unordered_set<std::string_view> taken = {"x", "y", "z"};
  if (cloud.has_normals()) taken.insert({"nx", "ny", "nz"});
  for (const PointProperty& extra : cloud.extras) {
    if (!is_valid_name(extra.name))
      throw_write_error(path, "the property name " + quoted(extra.name) +
                                  " is empty or contains blanks or control characters");
    if (!taken.insert(extra.name).second)
      throw_write_error(path, "two vertex properties are named " + quoted(extra.name));
  }
  std::unordered_set<std::string_view> elements = {"vertex"};
  for (const OtherElement& element : cloud.other_elements) {
    if (!is_valid_name(element.name))
      throw_write_error(path, "the element name " + quoted(element.name) +
                                  " is empty or contains blanks or control characters");
    if (!elements.insert(element.name).second)
      throw_write_error(path, "two elements are named " + quoted(element.name));
    if (element.properties.empty())
      throw_write_error(path, "element " + quoted(element.name) + " has no properties");
    for (const ElementProperty& p : element.properties) {
      if (!is_valid_name(p.name))
        throw_write_error(path, "the property name " + quoted(p.name) + " of element " +
                                    quoted(element.name) +
                                    " is empty or contains blanks or control characters");
      if (p.is_list && !is_integer_type(p.count_type))
        throw_write_error(path, "the list property " + quoted(p.name) +
                                    " has a count type that is not an integer type");
    }
  }
  for (const std::string& comment : cloud.comments)
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw_write_error(path, "a comment contains a line break");
}

// Positions and normals are written as float or double; anything else asked
// for (an integer type) would lose the filtered values, so it becomes double.
// Float is kept only while every value fits it: a filtered coordinate beyond
// float's range would otherwise be written as inf and the file could not be
// read back.
ScalarType written_type(ScalarType requested, const Matrix3& values) {
  if (requested != ScalarType::Float32) return ScalarType::Float64;
  const double largest = values.size() == 0 ? 0.0 : values.cwiseAbs().maxCoeff();
  return largest <= std::numeric_limits<float>::max() ? ScalarType::Float32 : ScalarType::Float64;
}

std::string header_text(const PointCloud& cloud, PlyEncoding encoding) {
  std::string h = "ply\nformat ";
  h += encoding == PlyEncoding::Ascii                ? "ascii"
       : encoding == PlyEncoding::BinaryLittleEndian ? "binary_little_endian"
                                                     : "binary_big_endian";
  h += " 1.0\n";
  for (const std::string& comment : cloud.comments) h += "comment " + comment + "\n";
  h += "element vertex " + std::to_string(cloud.size()) + "\n";
  const std::string position_type =
      ply_type_name(written_type(cloud.position_type, cloud.positions));
  const std::string normal_type = ply_type_name(written_type(cloud.normal_type, cloud.normals));
  for (const char* name : {"x", "y", "z"}) h += "property " + position_type + " " + name + "\n";
  if (cloud.has_normals())
    for (const char* name : {"nx", "ny", "nz"}) h += "property " + normal_type + " " + name + "\n";
  for (const PointProperty& extra : cloud.extras)
    h += std::string("property ") + ply_type_name(extra.type) + " " + extra.name + "\n";
  for (const OtherElement& element : cloud.other_elements) {
    h += "element " + element.name + " " + std::to_string(element.size()) + "\n";
    for (const ElementProperty& p : element.properties) {
      h += "property ";
      if (p.is_list) h += std::string("list ") + ply_type_name(p.count_type) + " ";
      h += std::string(ply_type_name(p.type)) + " " + p.name + "\n";
    }
  }
  return h + "end_header\n";
}

std::string value_text(double value) {
  std::string s;
  append_scalar_text(s, value, ScalarType::Float64);
  return s;
}

void write_other_element(RowWriter& writer, const OtherElement& element, const std::string& path) {
  auto fail = [&](std::size_t row, const std::string& what) {
    throw_write_error(path, "row " + std::to_string(row + 1) + " of element " +
                                quoted(element.name) + ": " + what);
  };
  auto emit = [&](std::size_t row, double value, ScalarType type, const ElementProperty& p) {
    if (!fits_scalar(value, type))
      fail(row, "the value " + value_text(value) + " of property " + quoted(p.name) +
                    " does not fit its type " + ply_type_name(type));
    writer.value(value, type);
  };
  const auto& offsets = element.row_offsets;
  for (std::size_t row = 0; row < element.size(); ++row) {
    const std::uint64_t begin = offsets[row], end = offsets[row + 1];
    if (begin > end || end > element.values.size()) fail(row, "row_offsets are out of order");
    std::uint64_t k = begin;
    for (const ElementProperty& p : element.properties) {
      if (k >= end) fail(row, "fewer values than properties");
      if (!p.is_list) {
        emit(row, element.values[k++], p.type, p);
        continue;
      }
      const double count = element.values[k++];
      emit(row, count, p.count_type, p);
      if (count < 0) fail(row, "list " + quoted(p.name) + " has a negative count");
      if (count > static_cast<double>(end - k))
        fail(row, "list " + quoted(p.name) + " has fewer items than its count");
      for (std::uint64_t j = 0; j < static_cast<std::uint64_t>(count); ++j)
        emit(row, element.values[k++], p.type, p);
    }
    if (k != end) fail(row, "more values than properties");
    writer.end_row();
  }
}

}  // namespace

void write_ply(OutputBuffer& out, const PointCloud& cloud, PlyEncoding encoding,
               const std::string& path) {
  check_names(cloud, path);
  for (const PointProperty& extra : cloud.extras)
    for (std::size_t i = 0; i < extra.values.size(); ++i)
      if (!fits_scalar(extra.values[i], extra.type))
        throw_write_error(path, "the value " + value_text(extra.values[i]) + " of property " +
                                    quoted(extra.name) + " at point " + std::to_string(i) +
                                    " does not fit its type " + ply_type_name(extra.type));
  out.text() += header_text(cloud, encoding);

  RowWriter writer(out, encoding);
  const bool normals = cloud.has_normals();
  const ScalarType position_type = written_type(cloud.position_type, cloud.positions);
  const ScalarType normal_type = written_type(cloud.normal_type, cloud.normals);
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i) {
    for (int d = 0; d < 3; ++d) writer.value(cloud.positions(i, d), position_type);
    if (normals)
      for (int d = 0; d < 3; ++d) writer.value(cloud.normals(i, d), normal_type);
    for (const PointProperty& extra : cloud.extras)
      writer.value(extra.values[static_cast<std::size_t>(i)], extra.type);
    writer.end_row();
  }
  for (const OtherElement& element : cloud.other_elements)
    write_other_element(writer, element, path);
}

}  // namespace detexture::io_detail
