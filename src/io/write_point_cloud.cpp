#include "detexture/io/write_point_cloud.h"

#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include "detexture/io/output_file.h"
#include "io_text.h"
#include "output_buffer.h"
#include "write_obj.h"
#include "write_off.h"
#include "write_pcd.h"
#include "write_ply.h"
#include "write_stl.h"
#include "write_xyz.h"

namespace detexture {
namespace {

namespace fs = std::filesystem;
using io_detail::throw_write_error;

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec) && !ec) return true;
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

void check_cloud(const PointCloud& cloud, const std::string& path) {
  const std::size_t n = cloud.size();
  if (n == 0) throw_write_error(path, "the point cloud is empty");
  if (cloud.normals.rows() != 0 && cloud.normals.rows() != cloud.positions.rows())
    throw_write_error(path, "the cloud has " + std::to_string(n) + " points but " +
                                std::to_string(cloud.normals.rows()) + " normals");
  for (const PointProperty& extra : cloud.extras)
    if (extra.values.size() != n)
      throw_write_error(path, "property '" + extra.name + "' has " +
                                  std::to_string(extra.values.size()) + " values for " +
                                  std::to_string(n) + " points");
  for (Eigen::Index i = 0; i < cloud.positions.rows(); ++i)
    if (!cloud.positions.row(i).allFinite())
      throw_write_error(path,
                        "point " + std::to_string(i) +
                            " has a NaN or infinite coordinate, which could not be read back");
}

}  // namespace

void check_write_options(const std::string& path, const WriteOptions& options) {
  const FileFormat format =
      options.format == FileFormat::Auto ? format_from_extension(path) : options.format;
  if (options.compressed && format != FileFormat::Pcd)
    throw std::invalid_argument("'" + path +
                                "': compressed output (binary-compressed) is only for PCD files");
  if (options.encoding == PlyEncoding::BinaryBigEndian && format != FileFormat::Ply &&
      format != FileFormat::Xyz)
    throw std::invalid_argument("'" + path + "': big-endian output is only for PLY files");
}

void write_point_cloud(const std::string& path, const PointCloud& cloud,
                       const WriteOptions& options) {
  const FileFormat format =
      options.format == FileFormat::Auto ? format_from_extension(path) : options.format;
  if (!options.protect_path.empty() && same_file(path, options.protect_path))
    throw_write_error(path, "it is the input file '" + options.protect_path +
                                "'; refusing to overwrite it, choose another output path");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw_write_error(path, "it is a directory");
  check_cloud(cloud, path);
  check_write_options(path, options);
  const bool ascii = options.encoding == PlyEncoding::Ascii;

  OutputFile file(path);
  io_detail::OutputBuffer out(file.get(), path);
  if (format == FileFormat::Ply) {
    io_detail::write_ply(out, cloud, options.encoding, path);
  } else if (format == FileFormat::Obj) {
    io_detail::write_obj(out, cloud, path, options.notices);
  } else if (format == FileFormat::Off) {
    io_detail::write_off(out, cloud, path, options.notices);
  } else if (format == FileFormat::Stl) {
    io_detail::write_stl(out, cloud, ascii, path, options.notices);
  } else if (format == FileFormat::Pcd) {
    io_detail::write_pcd(out, cloud,
                         ascii                ? io_detail::PcdData::Ascii
                         : options.compressed ? io_detail::PcdData::BinaryCompressed
                                              : io_detail::PcdData::Binary,
                         path, options.notices);
  } else {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool csv = ext == ".csv";
    io_detail::write_xyz(out, cloud, csv ? ',' : ' ');
  }
  out.flush();
  file.commit();
}

}  // namespace detexture
