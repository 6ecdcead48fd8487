#include "detexture/types.h"

namespace detexture {

double bounding_box_diagonal(const Positions& P) {
  if (P.rows() < 2) return 0.0;
  return (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
}

}  // namespace detexture
