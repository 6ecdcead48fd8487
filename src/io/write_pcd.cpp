#include "write_pcd.h"

#include <lzf.h>

#include <cstring>
#include <limits>
#include <unordered_set>

#include "scalar_codec.h"
#include "write_mesh_common.h"

namespace detexture::io_detail {
namespace {

ScalarType float_or_double(ScalarType requested, const Matrix3& values) {
  if (requested != ScalarType::Float32) return ScalarType::Float64;
  const double largest = values.size() == 0 ? 0.0 : values.cwiseAbs().maxCoeff();
  return largest <= std::numeric_limits<float>::max() ? ScalarType::Float32 : ScalarType::Float64;
}

// One field of the output: a column of positions or normals, the packed
// colour, or an extra.
struct OutField {
  std::string name;
  ScalarType type;
  const Matrix3* matrix = nullptr;  ///< positions or normals, with column
  int column = 0;
  const PointProperty* extra = nullptr;
  bool packed_color = false;
};

}  // namespace

void write_pcd(OutputBuffer& out, const PointCloud& cloud, PcdData data, const std::string& path,
               std::vector<std::string>* notices) {
  std::vector<OutField> fields;
  const ScalarType position_type = float_or_double(cloud.position_type, cloud.positions);
  const char* axes[] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) fields.push_back({axes[d], position_type, &cloud.positions, d});
  if (cloud.has_normals()) {
    const ScalarType normal_type = float_or_double(cloud.normal_type, cloud.normals);
    const char* names[] = {"normal_x", "normal_y", "normal_z"};
    for (int d = 0; d < 3; ++d) fields.push_back({names[d], normal_type, &cloud.normals, d});
  }
  int color[4] = {find_extra(cloud, "red"), find_extra(cloud, "green"), find_extra(cloud, "blue"),
                  find_extra(cloud, "alpha")};
  bool packed = true;
  for (int c = 0; c < 3; ++c)
    packed = packed && color[c] >= 0 &&
             cloud.extras[static_cast<std::size_t>(color[c])].type == ScalarType::UInt8;
  if (color[3] >= 0 && cloud.extras[static_cast<std::size_t>(color[3])].type != ScalarType::UInt8)
    color[3] = -1;
  // As PCL's point types: rgb is a float holding the bits 0x00RRGGBB (a tiny
  // number, never NaN), rgba a uint32 0xAARRGGBB.
  if (packed)
    fields.push_back(
        {color[3] >= 0 ? "rgba" : "rgb", color[3] >= 0 ? ScalarType::UInt32 : ScalarType::Float32});
  if (packed) fields.back().packed_color = true;
  std::unordered_set<std::string> taken;
  for (const OutField& f : fields) taken.insert(f.name);
  for (std::size_t k = 0; k < cloud.extras.size(); ++k) {
    const int index = static_cast<int>(k);
    if (packed &&
        (index == color[0] || index == color[1] || index == color[2] || index == color[3]))
      continue;
    const PointProperty& p = cloud.extras[k];
    bool valid = !p.name.empty();
    for (char c : p.name) valid = valid && static_cast<unsigned char>(c) > ' ' && c != 0x7f;
    if (!valid)
      throw_write_error(path, "the property name " + quoted(p.name) +
                                  " is empty or contains blanks or control characters");
    if (!taken.insert(p.name).second)
      throw_write_error(path, "two fields would be named " + quoted(p.name));
    OutField f{p.name, p.type};
    f.extra = &p;
    fields.push_back(f);
    for (double v : p.values)
      if (!fits_scalar(v, p.type))
        throw_write_error(path, "a value of property " + quoted(p.name) +
                                    " does not fit its type " + ply_type_name(p.type));
  }
  if (notices)
    for (const OtherElement& e : cloud.other_elements)
      notices->push_back("PCD holds points only: the element '" + e.name + "' (" +
                         std::to_string(e.size()) + " rows) is left out");

  const std::size_t n = cloud.size();
  std::string& text = out.text();
  text += "# .PCD v0.7 - Point Cloud Data file format\n";
  for (const std::string& comment : cloud.comments) {
    if (comment.find_first_of("\r\n") != std::string::npos)
      throw_write_error(path, "a comment contains a line break");
    text += "# " + comment + "\n";
  }
  text += "VERSION 0.7\nFIELDS";
  for (const OutField& f : fields) text += " " + f.name;
  text += "\nSIZE";
  for (const OutField& f : fields) text += " " + std::to_string(scalar_size(f.type));
  text += "\nTYPE";
  for (const OutField& f : fields) text += std::string(" ") + pcd_type_letter(f.type);
  text += "\nCOUNT";
  for (std::size_t k = 0; k < fields.size(); ++k) text += " 1";
  text += "\nWIDTH " + std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
          std::to_string(n) + "\nDATA " +
          (data == PcdData::Ascii    ? "ascii"
           : data == PcdData::Binary ? "binary"
                                     : "binary_compressed") +
          "\n";

  auto value = [&](const OutField& f, std::size_t i) -> double {
    if (f.matrix) return (*f.matrix)(static_cast<Eigen::Index>(i), f.column);
    if (f.extra) return f.extra->values[i];
    std::uint32_t bits = 0;
    for (int c = 0; c < 4; ++c) {
      const int k = color[c];
      const std::uint32_t byte =
          k < 0 ? 0
                : static_cast<std::uint32_t>(cloud.extras[static_cast<std::size_t>(k)].values[i]);
      bits |= byte << (c == 3 ? 24 : 16 - 8 * c);
    }
    return bits;
  };
  // The packed colour as the value its field type reads: for a float field
  // the float whose bits are the colour.
  auto packed_value = [&](const OutField& f, std::size_t i) -> double {
    const double v = value(f, i);
    if (!f.packed_color || f.type != ScalarType::Float32) return v;
    const auto bits = static_cast<std::uint32_t>(v);
    float as_float = 0.0f;
    std::memcpy(&as_float, &bits, 4);
    return as_float;
  };
  const bool swap = !host_is_little_endian();
  auto encode = [&](unsigned char* at, const OutField& f, std::size_t i) {
    if (f.packed_color)
      store_bytes(at, static_cast<std::uint32_t>(value(f, i)), swap);
    else
      encode_scalar(at, value(f, i), f.type, swap);
  };
  if (data == PcdData::Ascii) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < fields.size(); ++k) {
        if (k > 0) text += ' ';
        append_scalar_text(text, packed_value(fields[k], i), fields[k].type);
      }
      text += '\n';
      out.maybe_flush();
    }
    return;
  }
  if (data == PcdData::Binary) {
    unsigned char bytes[8];
    for (std::size_t i = 0; i < n; ++i) {
      for (const OutField& f : fields) {
        encode(bytes, f, i);
        out.append(bytes, scalar_size(f.type));
      }
      out.maybe_flush();
    }
    return;
  }
  // binary_compressed: the values field after field, LZF-compressed, after
  // the compressed and the uncompressed size (uint32 each).
  std::size_t point_bytes = 0;
  for (const OutField& f : fields) point_bytes += scalar_size(f.type);
  if (n > 0xffffffffull / point_bytes)
    throw_write_error(path,
                      "the cloud is larger than binary_compressed PCD can hold (4 GiB); "
                      "use --encoding binary");
  std::vector<unsigned char> plain(n * point_bytes);
  std::size_t at = 0;
  for (const OutField& f : fields) {
    const int size = scalar_size(f.type);
    for (std::size_t i = 0; i < n; ++i, at += size) encode(&plain[at], f, i);
  }
  std::vector<unsigned char> packed_bytes(plain.size() + plain.size() / 16 + 64);
  const unsigned int length =
      lzf_compress(plain.data(), static_cast<unsigned int>(plain.size()), packed_bytes.data(),
                   static_cast<unsigned int>(packed_bytes.size()));
  if (length == 0) throw_write_error(path, "LZF compression failed");
  unsigned char sizes[8];
  store_bytes(sizes, static_cast<std::uint32_t>(length), swap);
  store_bytes(sizes + 4, static_cast<std::uint32_t>(plain.size()), swap);
  out.append(sizes, 8);
  out.append(packed_bytes.data(), length);
}

}  // namespace detexture::io_detail
