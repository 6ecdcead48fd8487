#include "detexture/types.h"

#include <cstdio>

namespace detexture {

std::string number_text(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

double bounding_box_diagonal(const Positions& P) {
  if (P.rows() < 2) return 0.0;
  return (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();
}

}  // namespace detexture
