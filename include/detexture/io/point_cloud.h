// A point cloud as read from and written to disk: positions, optional normals,
// and everything else the file carried, so that it survives a round trip.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "detexture/types.h"

namespace detexture {

/// Scalar types of the PLY format. Values are held as double, which is exact
/// for every one of them.
enum class ScalarType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

/// Name used when writing a PLY header ("char", "uchar", ..., "double").
const char* ply_type_name(ScalarType type);
/// Size in bytes of one value of the type.
int scalar_size(ScalarType type);

/// A per-point property other than x, y, z, nx, ny, nz (colours, intensity,
/// labels, ...), kept in its original type. values has one entry per point.
struct PointProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;
  std::vector<double> values;
};

/// A non-vertex PLY element (faces, edges, ...), carried through unchanged.
/// Each row holds the values of all properties in order; a list property
/// contributes its count followed by its items.
struct ElementProperty {
  std::string name;
  ScalarType type = ScalarType::Int32;
  bool is_list = false;
  ScalarType count_type = ScalarType::UInt8;  ///< only for lists
};
struct OtherElement {
  std::string name;
  std::vector<ElementProperty> properties;
  std::vector<std::uint64_t> row_offsets;  ///< #rows+1 offsets into values
  std::vector<double> values;
  std::size_t size() const { return row_offsets.empty() ? 0 : row_offsets.size() - 1; }
};

struct PointCloud {
  Positions positions;                       ///< #P by 3
  Normals normals;                           ///< #P by 3, or 0 rows when the file had none
  std::vector<PointProperty> extras;         ///< other per-vertex properties, in file order
  std::vector<OtherElement> other_elements;  ///< non-vertex elements, in file order
  /// PLY comment lines without "comment "; obj_info lines as "obj_info ...".
  std::vector<std::string> comments;
  /// Precision of x, y, z (and of nx, ny, nz) in a PLY output: Float32 or
  /// Float64 (any other type is written as Float64). The reader sets Float32
  /// only when the file stored all three as float, so outputs keep the input's
  /// size; one double component (float x, double y z) makes all three double.
  /// The writer also uses double when a value lies beyond float's range.
  ScalarType position_type = ScalarType::Float64;
  ScalarType normal_type = ScalarType::Float64;

  std::size_t size() const { return static_cast<std::size_t>(positions.rows()); }
  bool has_normals() const { return normals.rows() == positions.rows() && normals.rows() > 0; }
};

}  // namespace detexture
