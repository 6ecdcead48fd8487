#include "detexture/types.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace detexture {

std::string number_text(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

double bounding_box_diagonal(const Positions& P) {
  if (P.rows() < 2) return 0.0;
  // The extent divided by its largest component before squaring, so that
  // neither 1e300 (overflow to inf) nor 1e-300 (underflow to 0) is lost.
  // The extent itself overflows only beyond ±8.9e307, half the largest double.
  const Eigen::RowVector3d extent = P.colwise().maxCoeff() - P.colwise().minCoeff();
  const double squared = extent.squaredNorm();
  if (std::isfinite(squared) && squared >= std::numeric_limits<double>::min())
    return std::sqrt(squared);  // the common case, unchanged to the last bit
  const double largest = extent.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return largest;
  return largest * (extent / largest).norm();
}

}  // namespace detexture
