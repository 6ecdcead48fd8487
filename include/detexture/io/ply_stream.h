// Binary PLY point clouds read and written a block of vertex records at a
// time, for clouds larger than memory (the out-of-core tiled run, and
// `detexture synth` at tens of millions of points). The record bytes are
// kept as they are, so every other property survives untouched.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"

namespace detexture {

struct PlyVertexField {
  std::string name;
  ScalarType type = ScalarType::Float32;
  std::size_t offset = 0;  ///< in the record, bytes
};

/// The vertex records of a binary PLY file: fixed-size, fields in order.
struct PlyVertexLayout {
  std::vector<PlyVertexField> fields;
  std::size_t record_size = 0;
  bool big_endian = false;
  std::uint64_t count = 0;            ///< vertices
  std::vector<std::string> comments;  ///< as PointCloud::comments
  int x = -1, y = -1, z = -1;         ///< field indices
  int nx = -1, ny = -1, nz = -1;      ///< -1 without normals
  bool has_normals() const { return nx >= 0 && ny >= 0 && nz >= 0; }
};

/// The layout of a result written by the out-of-core run: x y z in the
/// input's position type (float when all three were float, as
/// write_point_cloud does), nx ny nz (the input's normal type; double when the
/// input had none), then every other field in file order, little endian.
/// Its bytes match write_point_cloud's binary output for the same values.
PlyVertexLayout result_layout(const PlyVertexLayout& input, std::uint64_t count);

/// A layout of x y z [nx ny nz] in `real` followed by `extras` (name, type).
PlyVertexLayout make_layout(ScalarType real, bool normals,
                            const std::vector<std::pair<std::string, ScalarType>>& extras,
                            std::uint64_t count, const std::vector<std::string>& comments);

/// The header of a binary little-endian file with this layout.
std::string ply_header_text(const PlyVertexLayout& layout);

/// Reads the vertex records of a binary PLY file in blocks. Throws
/// std::runtime_error naming the file for an ASCII file, a vertex element
/// that is not the first or has list properties, other elements with rows
/// (faces: not supported out of core), missing x, y or z, or a file shorter
/// than its header says.
class PlyVertexReader {
 public:
  explicit PlyVertexReader(const std::string& path);
  ~PlyVertexReader();
  PlyVertexReader(const PlyVertexReader&) = delete;
  PlyVertexReader& operator=(const PlyVertexReader&) = delete;
  const PlyVertexLayout& layout() const { return layout_; }
  /// Read up to `max_records` records into *buffer (resized); returns the
  /// number read, 0 once all were read.
  std::size_t read(std::size_t max_records, std::vector<unsigned char>* buffer);
  /// Back to the first record.
  void rewind();
  /// Index of the next record to be read.
  std::uint64_t position() const { return next_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::size_t data_offset_ = 0;
  std::uint64_t next_ = 0;
  PlyVertexLayout layout_;
};

/// The value of field `f` of a record.
double record_value(const PlyVertexLayout& layout, int f, const unsigned char* record);
/// x y z of a record; throws std::runtime_error naming `path` and the vertex
/// (`index`) when a coordinate is not finite, as read_point_cloud does.
Eigen::Vector3d record_position(const PlyVertexLayout& layout, const unsigned char* record,
                                std::uint64_t index, const std::string& path);
/// nx ny nz of a record, normalized as read_point_cloud normalizes (unit
/// normals kept bit for bit; zero, NaN or infinite ones become zero).
Eigen::Vector3d record_normal(const PlyVertexLayout& layout, const unsigned char* record);

/// Write `out` (result_layout of `in`): position p, normal n, the other
/// fields copied from the input record.
void encode_result_record(const PlyVertexLayout& in, const unsigned char* in_record,
                          const PlyVertexLayout& out, const Eigen::Vector3d& p,
                          const Eigen::Vector3d& n, unsigned char* out_record);

/// Write field f of a little-endian record.
void encode_field(const PlyVertexLayout& layout, int f, double value, unsigned char* record);

}  // namespace detexture
