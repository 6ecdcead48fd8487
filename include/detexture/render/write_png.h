// Writing an Image as a PNG file (libpng).
#pragma once

#include <string>

#include "detexture/render/render_point_cloud.h"

namespace detexture {

/// Write image as an 8-bit RGB PNG, atomically: the data goes to a temporary
/// file in the target folder, renamed over `path` only when complete, so a
/// failure never leaves a half-written file nor touches an existing one.
///
/// Throws std::runtime_error with a sentence naming the file when it cannot
/// be created or written (or `path` is a folder), and std::invalid_argument
/// for an image whose size and pixel buffer disagree.
void write_png(const std::string& path, const Image& image);

}  // namespace detexture
