// Reading point clouds: PLY (ascii, binary little/big endian) and XYZ-style
// text (.xyz .xyzn .txt .pts).
#pragma once

#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"

namespace detexture {

enum class FileFormat { Auto, Ply, Xyz };

/// Parse "auto", "ply" or "xyz" (as given to --format); throws
/// std::invalid_argument with a sentence for anything else.
FileFormat parse_file_format(const std::string& name);

/// The format implied by a path's extension (.ply -> Ply; .xyz .xyzn .txt
/// .pts .csv -> Xyz); throws std::runtime_error naming the path when the
/// extension is unknown.
FileFormat format_from_extension(const std::string& path);

struct ReadReport {
  std::size_t zero_length_normals = 0;  ///< input normals of zero length (re-estimated later)
  std::vector<std::string> notices;     ///< human-readable notes (skipped elements, ...)
};

/// Read a point cloud. Throws std::runtime_error whose message names the file
/// and says what is wrong and where (line or byte offset) for: a missing or
/// unreadable file, a bad or unsupported header, truncated binary data, a
/// vertex count that does not match the data, a non-numeric token, NaN or Inf
/// coordinates, missing x/y/z, an empty cloud, or an unknown format.
/// Points with NaN or Inf coordinates are refused, not dropped: dropping would
/// silently break the correspondence with faces and with other files.
/// Input normals are normalized; zero-length ones stay (0,0,0), are counted
/// in the report, and are re-estimated by the pipeline (orient_normals.h).
PointCloud read_point_cloud(const std::string& path, FileFormat format = FileFormat::Auto,
                            ReadReport* report = nullptr);

}  // namespace detexture
