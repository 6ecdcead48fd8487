// Writing point clouds: PLY (ascii, binary little or big endian) and XYZ text.
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
/// never leaves a half-written file nor touches an existing one (OutputFile in
/// output_file.h: a symbolic link is followed and stays a link; a character
/// device such as /dev/null, or a FIFO, is written directly, never replaced).
///
/// PLY: the comments, then the vertex element with x y z (and nx ny nz) as
/// double and the extras in their own types, then the other elements in
/// order. Ascii values are written in the shortest text that reads back
/// exactly. XYZ: one line "x y z" per point, or "x y z nx ny nz extras..."
/// when the cloud has normals (without normals, extras are left out, since a
/// fourth column would read back as a normal); separated by commas for .csv,
/// by spaces otherwise; other elements and comments are left out.
///
/// Throws std::runtime_error with a sentence naming the file when `path` is
/// the protected input (same file after resolving ".", "..", links), when the
/// extension is unknown and format is Auto, when the file cannot be created
/// or written, or for a cloud that could not be read back: empty, a NaN or
/// Inf coordinate, sizes that disagree, an invalid or duplicate name, an
/// extra or element value that does not fit its integer type.
void write_point_cloud(const std::string& path, const PointCloud& cloud,
                       const WriteOptions& options = {});

}  // namespace detexture
