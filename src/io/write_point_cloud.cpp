#include "detexture/io/write_point_cloud.h"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <system_error>

#include "io_text.h"
#include "output_buffer.h"
#include "write_ply.h"
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

// A file created next to the target and renamed over it by commit(); removed
// again if commit() is never reached.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::string& target) : target_(target) {
    const fs::path target_path(target);
    if (!target_path.has_filename()) throw_write_error(target, "the path names no file");
    const fs::path folder =
        target_path.parent_path().empty() ? fs::path(".") : target_path.parent_path();
    std::random_device device;
    std::mt19937_64 rng((std::uint64_t(device()) << 32) ^ device());
    for (int attempt = 0; attempt < 100 && !file_; ++attempt) {
      char suffix[32];
      std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(rng()));
      temp_ = (folder / ("." + target_path.filename().string() + suffix)).string();
      // "x": fail rather than reuse a file that exists (C11, glibc).
      file_ = std::fopen(temp_.c_str(), "wbx");
      if (!file_ && errno != EEXIST) break;
    }
    if (!file_)
      throw_write_error(target,
                        "cannot create a file in " + folder.string() + ": " + std::strerror(errno));
  }

  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  ~TemporaryFile() {
    if (file_) std::fclose(file_);
    if (!committed_) {
      std::error_code ec;
      fs::remove(temp_, ec);
    }
  }

  std::FILE* get() const { return file_; }

  void commit() {
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!closed) throw_write_error(target_, std::string("writing failed: ") + std::strerror(errno));
    std::error_code ec;
    fs::rename(temp_, target_, ec);
    if (ec) throw_write_error(target_, "cannot replace the file: " + ec.message());
    committed_ = true;
  }

 private:
  std::string target_;
  std::string temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

}  // namespace

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

  TemporaryFile file(path);
  io_detail::OutputBuffer out(file.get(), path);
  if (format == FileFormat::Ply) {
    io_detail::write_ply(out, cloud, options.encoding, path);
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
