#include "detexture/io/point_cloud.h"

namespace detexture {

const char* ply_type_name(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return "char";
    case ScalarType::UInt8:
      return "uchar";
    case ScalarType::Int16:
      return "short";
    case ScalarType::UInt16:
      return "ushort";
    case ScalarType::Int32:
      return "int";
    case ScalarType::UInt32:
      return "uint";
    case ScalarType::Float32:
      return "float";
    case ScalarType::Float64:
      return "double";
  }
  return "unknown";
}

int scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

}  // namespace detexture
