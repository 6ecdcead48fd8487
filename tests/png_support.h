// Reading a PNG back with libpng, for tests of the pictures.
#pragma once

#include <png.h>

#include <cstring>
#include <string>

#include "detexture/render/render_point_cloud.h"

namespace detexture::test {

/// The file as 8-bit RGB, via libpng's simplified API; width 0 if it cannot
/// be read.
inline Image read_png(const std::string& path) {
  Image image;
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return image;
  png.format = PNG_FORMAT_RGB;
  image.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, image.rgb.data(), 0, nullptr)) {
    png_image_free(&png);
    return Image();
  }
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  return image;
}

}  // namespace detexture::test
