// Reading point clouds and meshes: PLY (ascii, binary little/big endian),
// OBJ, OFF, STL (ascii, binary), PCD v0.7 (ascii, binary, binary_compressed)
// and XYZ-style text (.xyz .xyzn .txt .pts .csv). The faces of every mesh
// format end up where PLY keeps them: the "face" element with a
// vertex_indices list (face_list.h).
//
// PLY: every scalar type in both spellings (char/int8 ... double/float64).
// The "vertex" element needs x, y, z (any type); nx, ny, nz become normals
// when all three are present (otherwise they are kept as extras). Every other
// scalar vertex property goes to PointCloud::extras in its original type;
// list properties of the vertex element are skipped with a notice. Other
// elements (faces, edges, ...) go to PointCloud::other_elements, comment and
// obj_info lines to PointCloud::comments ("obj_info ..." kept whole). Ascii
// rows are one per line; CRLF and lone CR line endings are accepted. An
// unknown header line before the first element (old Blender's bare "Created
// by ...") is kept as a comment, with a notice. Bytes after the last
// element of a binary file are ignored with a notice; in an ascii file any
// further non-blank line is an error.
//
// OBJ: "v x y z" (also "x y z w", whose w is ignored, and "x y z r g b",
// whose colours become float extras red, green, blue), "vn" and "f" with
// 1-based or negative indices in any of the forms v, v/vt, v//vn, v/vt/vn;
// polygons are kept as they are. OBJ normals belong to face corners: they
// become vertex normals when every corner of a vertex names the same one,
// and are left out (with a notice) otherwise. Without faces, the i-th "vn"
// is the i-th vertex's. "vt", "p", "l", groups, materials and other
// statements are ignored with a notice. '#' starts a comment.
//
// OFF: "[C][N]OFF", the counts "vertices faces [edges]" (also on the first
// line), then one vertex per line (x y z, nx ny nz with N, r g b [a] with C:
// colours become uchar extras red green blue [alpha] when they are all
// integers 0-255, float extras otherwise), then one face per line "n i1 ...
// in" (0-based; face colours are ignored with a notice). '#' starts a
// comment.
//
// STL: binary when the file is exactly 84 + 50 n bytes for the n triangles
// it declares at byte 80 (even if it starts with "solid"), ascii otherwise
// (several solids are read as one). Corners at exactly the same position
// (-0 = +0) are welded into one vertex, numbered by first appearance, so a
// mesh comes out rather than a triangle soup. The facet normals are not kept
// (they are not vertex normals). Binary coordinates are floats.
//
// PCD: the header lines VERSION 0.7, FIELDS, SIZE, TYPE, COUNT, WIDTH,
// HEIGHT, VIEWPOINT, POINTS, DATA. x y z are required; normal_x normal_y
// normal_z become normals; rgb or rgba (4 bytes packed 0xAARRGGBB, type U or
// F) become uchar extras red green blue [alpha]; every other field becomes
// an extra in its type (a field of COUNT k becomes k extras name_0 ...
// name_k-1; padding fields "_" are skipped). 8-byte integer fields are
// refused. Points with a NaN or Inf coordinate (PCL's invalid points in an
// organized cloud) are dropped with a notice: PCD has no faces whose
// numbering this would break.
//
// XYZ: one point per line, "x y z" or "x y z nx ny nz ...", values separated
// by blanks or by commas (an empty field "1,,2" is an error). '#' starts a
// comment; blank lines are ignored. Lines end in "\n", "\r\n" or a lone
// "\r" (old Mac files). A first line holding a single integer is
// a .pts point count and must match the number of rows. Every row must have
// the same number of columns: 3, or at least 6. Columns after the sixth are
// kept as float64 extras named field6, field7, ... (0-based column index).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"

namespace detexture {

enum class FileFormat { Auto, Ply, Xyz, Obj, Off, Stl, Pcd };

/// Bounds on what the readers accept, so that a broken or hostile file fails
/// at once with a message naming it instead of exhausting memory or time.
/// Real files stay far below them.
/// A PLY header (up to and including "end_header"): 64 MiB, about 2.5 million
/// property lines.
constexpr std::size_t kMaxPlyHeaderBytes = std::size_t(64) << 20;
/// One line of an XYZ file: 1 MiB.
constexpr std::size_t kMaxTextLineBytes = std::size_t(1) << 20;
/// Columns of an XYZ row: x y z nx ny nz and up to 1018 extras.
constexpr std::size_t kMaxXyzColumns = 1024;
/// A pipe, device or other non-regular file (whose size is not known
/// beforehand) is read up to 4 GiB; the text and header bounds above are
/// also checked while it is read, so /dev/zero fails after its first bytes.
constexpr std::uint64_t kMaxStreamBytes = std::uint64_t(4) << 30;

/// Parse "auto", "ply", "xyz", "obj", "off", "stl" or "pcd" (as given to --format); throws
/// std::invalid_argument with a sentence for anything else.
FileFormat parse_file_format(const std::string& name);

/// The format implied by a path's extension, in any case (.ply -> Ply; .obj,
/// .off, .stl, .pcd -> Obj, Off, Stl, Pcd; .xyz .xyzn .pwn .txt .pts .csv ->
/// Xyz: known_extensions()); throws std::runtime_error naming the path when
/// the extension is unknown.
FileFormat format_from_extension(const std::string& path);

/// The extensions format_from_extension knows, lower case with the dot, as
/// ".ply, .obj, ..., .csv": for messages and the command line's help.
std::string known_extensions();

struct ReadReport {
  /// Input normals of zero length, or with a NaN or Inf component: set to
  /// (0,0,0) and counted, to be re-estimated later.
  std::size_t zero_length_normals = 0;
  std::vector<std::string> notices;  ///< human-readable notes (skipped elements, ...)
};

/// Read a point cloud. Throws std::runtime_error whose message names the file
/// and says what is wrong and where (line or byte offset) for: a missing or
/// unreadable file, a bad or unsupported header, truncated binary data, a
/// vertex count that does not match the data, a non-numeric token, NaN or Inf
/// coordinates, missing x/y/z, an empty cloud, an unknown format, or input
/// beyond the bounds above (kMaxPlyHeaderBytes, ...).
/// Points with NaN or Inf coordinates are refused, not dropped (except in
/// PCD, see above): dropping would silently break the correspondence with
/// faces and with other files.
/// Input normals are normalized; zero-length ones, and ones with a NaN or Inf
/// component, become (0,0,0), are counted in the report, and are re-estimated
/// by the pipeline (orient_normals.h). A declared count is checked against
/// the file size before anything is allocated for it. format Auto: from the
/// extension (format_from_extension).
PointCloud read_point_cloud(const std::string& path, FileFormat format = FileFormat::Auto,
                            ReadReport* report = nullptr);

/// Normalize normals N (#N by 3) in place as the readers do: rows of unit
/// length (to within 1e-12) are left bit-identical, zero-length rows and rows
/// with a NaN or Inf component become (0,0,0), to be re-estimated by the
/// pipeline. Returns how many became zero. For callers that pass normals from
/// memory (the Python module), so that they get what a file would give.
std::size_t normalize_normals(Normals& N);

}  // namespace detexture
