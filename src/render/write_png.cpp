#include "detexture/render/write_png.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

namespace detexture {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error("cannot write '" + path + "': " + what);
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * static_cast<std::size_t>(image.width) * image.height)
    throw std::invalid_argument("the image is " + std::to_string(image.width) + " x " +
                                std::to_string(image.height) + " pixels but holds " +
                                std::to_string(image.rgb.size()) + " bytes");
  const fs::path target(path);
  std::error_code ec;
  if (!target.has_filename()) fail(path, "the path names no file");
  if (fs::is_directory(target, ec)) fail(path, "it is a directory");
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();

  // A temporary file beside the target, renamed over it when complete.
  std::random_device device;
  std::mt19937_64 rng((std::uint64_t(device()) << 32) ^ device());
  std::string temp;
  std::FILE* file = nullptr;
  for (int attempt = 0; attempt < 100 && !file; ++attempt) {
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".%016llx.tmp", static_cast<unsigned long long>(rng()));
    temp = (folder / ("." + target.filename().string() + suffix)).string();
    file = std::fopen(temp.c_str(), "wbx");  // "x": never reuse an existing file
    if (!file && errno != EEXIST) break;
  }
  if (!file) fail(path, "cannot create a file in " + folder.string() + ": " + std::strerror(errno));

  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  const bool encoded = png_image_write_to_stdio(&png, file, 0, image.rgb.data(),
                                                static_cast<png_int_32>(3 * image.width), nullptr);
  const std::string message = png.message;
  png_image_free(&png);
  const bool flushed = std::fflush(file) == 0 && !std::ferror(file);
  const int flush_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!encoded || !flushed || !closed) {
    fs::remove(temp, ec);
    fail(path, !encoded ? "libpng: " + message
                        : std::string("writing failed: ") + std::strerror(flush_errno));
  }
  fs::rename(temp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    fail(path, "cannot replace the file: " + ec.message());
  }
}

}  // namespace detexture
