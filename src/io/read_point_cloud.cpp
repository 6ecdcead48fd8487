#include "detexture/io/read_point_cloud.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io_text.h"
#include "read_obj.h"
#include "read_off.h"
#include "read_pcd.h"
#include "read_ply.h"
#include "read_stl.h"
#include "read_xyz.h"

namespace detexture {

FileFormat parse_file_format(const std::string& name) {
  if (name == "auto") return FileFormat::Auto;
  if (name == "ply") return FileFormat::Ply;
  if (name == "xyz") return FileFormat::Xyz;
  if (name == "obj") return FileFormat::Obj;
  if (name == "off") return FileFormat::Off;
  if (name == "stl") return FileFormat::Stl;
  if (name == "pcd") return FileFormat::Pcd;
  throw std::invalid_argument("unknown file format '" + name +
                              "'; expected auto, ply, xyz, obj, off, stl or pcd");
}

namespace {

// The one list of extensions: format_from_extension, its message and the
// command line's help read it. `.pwn` is CGAL's name for x y z nx ny nz.
struct ExtensionFormat {
  const char* extension;
  FileFormat format;
};
constexpr ExtensionFormat kExtensions[] = {
    {".ply", FileFormat::Ply},  {".obj", FileFormat::Obj}, {".off", FileFormat::Off},
    {".stl", FileFormat::Stl},  {".pcd", FileFormat::Pcd}, {".xyz", FileFormat::Xyz},
    {".xyzn", FileFormat::Xyz}, {".pwn", FileFormat::Xyz}, {".txt", FileFormat::Xyz},
    {".pts", FileFormat::Xyz},  {".csv", FileFormat::Xyz}};

}  // namespace

std::string known_extensions() {
  std::string text;
  for (const ExtensionFormat& e : kExtensions)
    text += (text.empty() ? "" : ", ") + std::string(e.extension);
  return text;
}

FileFormat format_from_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const ExtensionFormat& e : kExtensions)
    if (ext == e.extension) return e.format;
  for (const char* other : {".las", ".laz", ".e57", ".gltf", ".glb", ".fbx", ".3ds", ".dae"})
    if (ext == other)
      throw std::runtime_error("'" + path + "': the " + ext.substr(1) +
                               " format is not supported (yet); convert it to .ply, e.g. with "
                               "MeshLab, CloudCompare or 'assimp export'");
  throw std::runtime_error("cannot tell the format of '" + path + "' from its extension" +
                           (ext.empty() ? std::string() : " '" + ext + "'") + "; use " +
                           known_extensions() +
                           ", or give the format explicitly (ply, obj, off, stl, pcd or xyz)");
}

namespace {

// Checks a pipe or device while it is read, since its size is not known
// beforehand: the same bounds as the parsers check on a regular file, applied
// as the bytes arrive, so that /dev/zero or an endless stream fails after its
// first bytes instead of after filling the memory.
class StreamBounds {
 public:
  StreamBounds(const std::string& path, FileFormat format) : path_(path), format_(format) {}

  void check(const std::string& bytes, std::size_t from) {
    if (bytes.size() > kMaxStreamBytes)
      io_detail::throw_read_error(path_, "",
                                  "a pipe or device is read up to " +
                                      std::to_string(kMaxStreamBytes >> 30) +
                                      " GiB; save it to a file first");
    if (format_ == FileFormat::Ply) {
      if (header_done_) return;
      if (bytes.size() >= 3 && bytes.compare(0, 3, "ply") != 0)
        io_detail::throw_read_error(path_, "line 1",
                                    "not a PLY file: the first line must be 'ply'");
      const std::size_t back = from >= 12 ? from - 12 : 0;
      if (bytes.find("end_header", back) != std::string::npos)
        header_done_ = true;
      else if (bytes.size() > kMaxPlyHeaderBytes)
        io_detail::throw_read_error(path_, "",
                                    "the header is longer than " +
                                        std::to_string(kMaxPlyHeaderBytes >> 20) +
                                        " MiB without an 'end_header' line");
      return;
    }
    if (format_ == FileFormat::Stl || format_ == FileFormat::Pcd) return;  // may be binary
    for (std::size_t i = from; i < bytes.size(); ++i) {
      if (bytes[i] == '\0')
        io_detail::throw_read_error(path_, "byte " + std::to_string(i),
                                    "a NUL byte; this is binary data, not a text point cloud");
      line_length_ = (bytes[i] == '\n' || bytes[i] == '\r') ? 0 : line_length_ + 1;
      if (line_length_ > kMaxTextLineBytes)
        io_detail::throw_read_error(path_, "byte " + std::to_string(i),
                                    "a line longer than " +
                                        std::to_string(kMaxTextLineBytes >> 20) +
                                        " MiB; this is not a text point cloud the reader accepts");
    }
  }

 private:
  const std::string& path_;
  FileFormat format_;
  bool header_done_ = false;
  std::size_t line_length_ = 0;
};

std::string read_file_bytes(const std::string& path, FileFormat format) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) io_detail::throw_read_error(path, "", "the file does not exist");
  if (fs::is_directory(status))
    io_detail::throw_read_error(path, "", "it is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) io_detail::throw_read_error(path, "", "the file cannot be opened (permissions?)");
  std::string bytes;
  const bool regular = fs::is_regular_file(status);
  if (regular) {
    const auto size = fs::file_size(path, ec);
    if (!ec) bytes.reserve(size);
  }
  StreamBounds bounds(path, format);
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    const std::size_t from = bytes.size();
    bytes.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (!regular) bounds.check(bytes, from);
  }
  if (in.bad()) io_detail::throw_read_error(path, "", "reading the file failed");
  return bytes;
}

}  // namespace

// Scale by the largest component first, so that tiny but non-zero normals
// do not underflow to zero length. Normals already of unit length (to
// within rounding) are left bit-identical, so a write-read round trip does
// not perturb them.
std::size_t normalize_normals(Normals& N) {
  std::size_t zero_length = 0;
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    auto n = N.row(i);
    const double largest = n.allFinite() ? n.cwiseAbs().maxCoeff() : 0.0;
    if (largest == 0.0) {
      n.setZero();
      ++zero_length;
      continue;
    }
    if (std::fabs(n.squaredNorm() - 1.0) <= 1e-12) continue;
    n /= largest;
    n /= n.norm();
  }
  return zero_length;
}

PointCloud read_point_cloud(const std::string& path, FileFormat format, ReadReport* report) {
  if (format == FileFormat::Auto) format = format_from_extension(path);
  const std::string bytes = read_file_bytes(path, format);
  ReadReport local;
  ReadReport& r = report ? *report : local;
  r = ReadReport{};
  PointCloud cloud;
  switch (format) {
    case FileFormat::Ply:
      cloud = io_detail::read_ply(bytes, path, r);
      break;
    case FileFormat::Obj:
      cloud = io_detail::read_obj(bytes, path, r);
      break;
    case FileFormat::Off:
      cloud = io_detail::read_off(bytes, path, r);
      break;
    case FileFormat::Stl:
      cloud = io_detail::read_stl(bytes, path, r);
      break;
    case FileFormat::Pcd:
      cloud = io_detail::read_pcd(bytes, path, r);
      break;
    default:
      cloud = io_detail::read_xyz(bytes, path, r);
      break;
  }
  r.zero_length_normals = normalize_normals(cloud.normals);
  return cloud;
}

}  // namespace detexture
