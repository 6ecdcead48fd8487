// Writing point clouds and meshes: PLY (ascii, binary little or big
// endian), OBJ, OFF, STL (ascii, binary), PCD (ascii, binary,
// binary_compressed) and XYZ text.
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "detexture/io/read_point_cloud.h"

namespace detexture {

enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct WriteOptions {
  FileFormat format = FileFormat::Auto;  ///< Auto: from the extension
  PlyEncoding encoding = PlyEncoding::BinaryLittleEndian;
  /// PCD only: binary_compressed (LZF) instead of binary. encoding Ascii
  /// gives ascii PLY, STL and PCD; the text formats ignore the encoding;
  /// BinaryBigEndian is refused for OBJ, OFF, STL and PCD.
  bool compressed = false;
  /// Path that must not be overwritten (the input); compared after resolving.
  std::string protect_path;
  /// When given, receives one sentence per thing the format cannot hold
  /// (extras in OBJ, vertex normals in STL, faces in PCD, ...).
  std::vector<std::string>* notices = nullptr;
};

/// Check, before any work, that options suit the format of path: throws
/// std::invalid_argument with a sentence for compressed output other than
/// PCD or big-endian output other than PLY (and XYZ, which ignores it), and
/// std::runtime_error when format is Auto and the extension is unknown.
void check_write_options(const std::string& path, const WriteOptions& options);

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
/// OBJ, OFF, STL, PCD: see write_obj.h, write_off.h, write_stl.h and
/// write_pcd.h in src/io: OBJ keeps positions, normals, red green blue and
/// the faces; OFF the same (colours in their type, no comments); STL only
/// the faces' triangles (and refuses a cloud without faces); PCD every vertex
/// property and no faces.
///
/// Throws std::runtime_error with a sentence naming the file when `path` is
/// the protected input (same file after resolving ".", "..", links), when the
/// extension is unknown and format is Auto, when the file cannot be created
/// or written, or for a cloud that could not be read back: empty, a NaN or
/// Inf coordinate, sizes that disagree, no faces for STL, an invalid or duplicate name, an
/// extra or element value that does not fit its integer type.
/// Throws std::invalid_argument for an encoding the format does not have
/// (check_write_options).
void write_point_cloud(const std::string& path, const PointCloud& cloud,
                       const WriteOptions& options = {});

}  // namespace detexture
