// Writing point clouds: PLY (ascii or binary little endian) and XYZ text.
#pragma once

#include <string>

#include "detexture/io/point_cloud.h"
#include "detexture/io/read_point_cloud.h"

namespace detexture {

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct WriteOptions {
  FileFormat format = FileFormat::Auto;  ///< Auto: from the extension
  PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;
  /// Path that must not be overwritten (the input); compared after resolving.
  std::string protect_path;
};

/// Write a point cloud atomically: the data goes to a temporary file in the
/// target folder, which is renamed over `path` only when complete, so a failure
/// never leaves a half-written file. Throws std::runtime_error with a sentence
/// naming the file when it cannot be written, or when `path` is the protected
/// input. PLY keeps extras in their types and carries other elements through;
/// XYZ writes x y z [nx ny nz].
void write_point_cloud(const std::string& path, const PointCloud& cloud,
                       const WriteOptions& options = {});

}  // namespace detexture
