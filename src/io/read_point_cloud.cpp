#include "detexture/io/read_point_cloud.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "io_text.h"
#include "read_ply.h"
#include "read_xyz.h"

namespace detexture {

FileFormat parse_file_format(const std::string& name) {
  if (name == "auto") return FileFormat::Auto;
  if (name == "ply") return FileFormat::Ply;
  if (name == "xyz") return FileFormat::Xyz;
  throw std::invalid_argument("unknown file format '" + name + "'; expected auto, ply or xyz");
}

FileFormat format_from_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".ply") return FileFormat::Ply;
  if (ext == ".xyz" || ext == ".xyzn" || ext == ".txt" || ext == ".pts" || ext == ".csv")
    return FileFormat::Xyz;
  throw std::runtime_error(
      "cannot tell the format of '" + path + "' from its extension" +
      (ext.empty() ? std::string() : " '" + ext + "'") +
      "; use .ply, .xyz, .xyzn, .txt, .pts or .csv, or give the format explicitly (ply or xyz)");
}

namespace {

std::string read_file_bytes(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) io_detail::throw_read_error(path, "", "the file does not exist");
  if (fs::is_directory(status))
    io_detail::throw_read_error(path, "", "it is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) io_detail::throw_read_error(path, "", "the file cannot be opened (permissions?)");
  std::string bytes;
  if (fs::is_regular_file(status)) {
    const auto size = fs::file_size(path, ec);
    if (!ec) bytes.reserve(size);
  }
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
    bytes.append(buffer, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) io_detail::throw_read_error(path, "", "reading the file failed");
  return bytes;
}

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

}  // namespace

PointCloud read_point_cloud(const std::string& path, FileFormat format, ReadReport* report) {
  if (format == FileFormat::Auto) format = format_from_extension(path);
  const std::string bytes = read_file_bytes(path);
  ReadReport local;
  ReadReport& r = report ? *report : local;
  r = ReadReport{};
  PointCloud cloud = format == FileFormat::Ply ? io_detail::read_ply(bytes, path, r)
                                               : io_detail::read_xyz(bytes, path, r);
  r.zero_length_normals = normalize_normals(cloud.normals);
  return cloud;
}

}  // namespace detexture
