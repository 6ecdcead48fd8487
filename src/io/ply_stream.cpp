#include "detexture/io/ply_stream.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "detexture/io/read_point_cloud.h"
#include "ply_header.h"
#include "scalar_codec.h"

namespace detexture {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("cannot stream '" + path + "': " + what);
}

void index_fields(PlyVertexLayout& L) {
  std::size_t offset = 0;
  for (std::size_t f = 0; f < L.fields.size(); ++f) {
    PlyVertexField& field = L.fields[f];
    field.offset = offset;
    offset += static_cast<std::size_t>(scalar_size(field.type));
    const int i = static_cast<int>(f);
    if (field.name == "x") L.x = i;
    if (field.name == "y") L.y = i;
    if (field.name == "z") L.z = i;
    if (field.name == "nx") L.nx = i;
    if (field.name == "ny") L.ny = i;
    if (field.name == "nz") L.nz = i;
  }
  L.record_size = offset;
}

bool all_float(const PlyVertexLayout& L, int a, int b, int c) {
  for (const int f : {a, b, c})
    if (f < 0 || L.fields[static_cast<std::size_t>(f)].type != ScalarType::Float32) return false;
  return true;
}

}  // namespace

PlyVertexLayout make_layout(ScalarType real, bool normals,
                            const std::vector<std::pair<std::string, ScalarType>>& extras,
                            std::uint64_t count, const std::vector<std::string>& comments) {
  PlyVertexLayout L;
  for (const char* name : {"x", "y", "z"}) L.fields.push_back({name, real, 0});
  if (normals)
    for (const char* name : {"nx", "ny", "nz"}) L.fields.push_back({name, real, 0});
  for (const auto& [name, type] : extras) L.fields.push_back({name, type, 0});
  L.count = count;
  L.comments = comments;
  index_fields(L);
  return L;
}

PlyVertexLayout result_layout(const PlyVertexLayout& in, std::uint64_t count) {
  PlyVertexLayout L;
  const ScalarType pos =
      all_float(in, in.x, in.y, in.z) ? ScalarType::Float32 : ScalarType::Float64;
  const ScalarType nor = in.has_normals() && all_float(in, in.nx, in.ny, in.nz)
                             ? ScalarType::Float32
                             : ScalarType::Float64;
  for (const char* name : {"x", "y", "z"}) L.fields.push_back({name, pos, 0});
  for (const char* name : {"nx", "ny", "nz"}) L.fields.push_back({name, nor, 0});
  for (const PlyVertexField& f : in.fields)
    if (f.name != "x" && f.name != "y" && f.name != "z" && f.name != "nx" && f.name != "ny" &&
        f.name != "nz")
      L.fields.push_back({f.name, f.type, 0});
  L.count = count;
  L.comments = in.comments;
  index_fields(L);
  return L;
}

std::string ply_header_text(const PlyVertexLayout& L) {
  std::string h = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& comment : L.comments) h += "comment " + comment + "\n";
  h += "element vertex " + std::to_string(L.count) + "\n";
  for (const PlyVertexField& f : L.fields)
    h += std::string("property ") + ply_type_name(f.type) + " " + f.name + "\n";
  return h + "end_header\n";
}

PlyVertexReader::PlyVertexReader(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "rb");
  if (!file_) fail(path, std::strerror(errno));
  std::string head;
  char block[1 << 16];
  std::size_t got;
  // The header ends at "end_header" and its line ending.
  while (head.find("end_header") == std::string::npos ||
         head.find('\n', head.find("end_header")) == std::string::npos) {
    got = std::fread(block, 1, sizeof block, file_);
    if (got == 0) break;
    head.append(block, got);
    if (head.size() > kMaxPlyHeaderBytes) break;
  }
  const io_detail::PlyHeader header = io_detail::parse_ply_header(head, path);
  if (header.encoding == PlyEncoding::Ascii)
    fail(path,
         "it is ASCII PLY; out-of-core runs read binary PLY (convert it with "
         "'detexture IN -o OUT.ply' once, or run in memory)");
  if (header.elements.empty() || header.elements[0].name != "vertex")
    fail(path, "the first element is not 'vertex'");
  for (std::size_t e = 1; e < header.elements.size(); ++e)
    if (header.elements[e].count > 0)
      fail(path, "it has " + std::to_string(header.elements[e].count) + " '" +
                     header.elements[e].name +
                     "' rows; out-of-core runs read point clouds without faces or other "
                     "elements");
  layout_.big_endian = header.encoding == PlyEncoding::BinaryBigEndian;
  layout_.count = header.elements[0].count;
  layout_.comments = header.comments;
  for (const io_detail::PlyProperty& p : header.elements[0].properties) {
    if (p.is_list) fail(path, "the vertex property '" + p.name + "' is a list");
    layout_.fields.push_back({p.name, p.type, 0});
  }
  index_fields(layout_);
  if (layout_.x < 0 || layout_.y < 0 || layout_.z < 0)
    fail(path, "the vertices have no x, y and z");
  if (layout_.nx >= 0 || layout_.ny >= 0 || layout_.nz >= 0) {
    if (!layout_.has_normals()) fail(path, "the vertices have some but not all of nx, ny, nz");
  }
  data_offset_ = header.data_offset;
  rewind();
}

PlyVertexReader::~PlyVertexReader() {
  if (file_) std::fclose(file_);
}

void PlyVertexReader::rewind() {
  if (std::fseek(file_, static_cast<long>(data_offset_), SEEK_SET) != 0)
    fail(path_, std::strerror(errno));
  next_ = 0;
}

std::size_t PlyVertexReader::read(std::size_t max_records, std::vector<unsigned char>* buffer) {
  const std::uint64_t left = layout_.count - next_;
  const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(left, max_records));
  buffer->resize(want * layout_.record_size);
  if (want == 0) return 0;
  const std::size_t got = std::fread(buffer->data(), layout_.record_size, want, file_);
  if (got != want)
    fail(path_, "the file ends at vertex " + std::to_string(next_ + got) + " of " +
                    std::to_string(layout_.count) + " (truncated?)");
  next_ += got;
  return got;
}

double record_value(const PlyVertexLayout& L, int f, const unsigned char* record) {
  const PlyVertexField& field = L.fields[static_cast<std::size_t>(f)];
  const bool swap = L.big_endian == io_detail::host_is_little_endian();
  return io_detail::decode_scalar(record + field.offset, field.type, swap);
}

Eigen::Vector3d record_position(const PlyVertexLayout& L, const unsigned char* record,
                                std::uint64_t index, const std::string& path) {
  const Eigen::Vector3d p(record_value(L, L.x, record), record_value(L, L.y, record),
                          record_value(L, L.z, record));
  if (!p.allFinite())
    throw std::runtime_error("'" + path + "', vertex " + std::to_string(index + 1) +
                             ": a NaN or infinite coordinate; such points are refused, not "
                             "dropped, since dropping them would break the numbering of the "
                             "vertices");
  return p;
}

Eigen::Vector3d record_normal(const PlyVertexLayout& L, const unsigned char* record) {
  Eigen::Vector3d n(record_value(L, L.nx, record), record_value(L, L.ny, record),
                    record_value(L, L.nz, record));
  // As read_point_cloud's normalize_normals.
  const double largest = n.allFinite() ? n.cwiseAbs().maxCoeff() : 0.0;
  if (largest == 0.0) return Eigen::Vector3d::Zero();
  if (std::fabs(n.squaredNorm() - 1.0) <= 1e-12) return n;
  n /= largest;
  n /= n.norm();
  return n;
}

void encode_field(const PlyVertexLayout& L, int f, double value, unsigned char* record) {
  const PlyVertexField& field = L.fields[static_cast<std::size_t>(f)];
  io_detail::encode_scalar(record + field.offset, value, field.type,
                           !io_detail::host_is_little_endian());
}

void encode_result_record(const PlyVertexLayout& in, const unsigned char* in_record,
                          const PlyVertexLayout& out, const Eigen::Vector3d& p,
                          const Eigen::Vector3d& n, unsigned char* out_record) {
  for (int d = 0; d < 3; ++d) {
    encode_field(out, d, p(d), out_record);
    encode_field(out, 3 + d, n(d), out_record);
  }
  const bool swap = in.big_endian != !io_detail::host_is_little_endian();
  std::size_t k = 6;
  for (std::size_t f = 0; f < in.fields.size(); ++f) {
    const int i = static_cast<int>(f);
    if (i == in.x || i == in.y || i == in.z || i == in.nx || i == in.ny || i == in.nz) continue;
    const PlyVertexField& src = in.fields[f];
    const PlyVertexField& dst = out.fields[k++];
    if (!swap) {
      std::memcpy(out_record + dst.offset, in_record + src.offset,
                  static_cast<std::size_t>(scalar_size(src.type)));
    } else {
      const int size = scalar_size(src.type);
      for (int b = 0; b < size; ++b)
        out_record[dst.offset + b] = in_record[src.offset + size - 1 - b];
    }
  }
}

}  // namespace detexture
