#include "detexture/geometry/spatial_order.h"

#include <algorithm>
#include <numeric>

namespace detexture {
namespace {

// Spread the low 21 bits of x so that there are two zero bits between each.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

std::vector<std::uint32_t> spatial_order(const Positions& P) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (n < 2) return order;
  const Eigen::RowVector3d lo = P.colwise().minCoeff();
  const double extent = (P.colwise().maxCoeff() - lo).maxCoeff();
  const double scale = extent > 0.0 ? (double((1 << 21) - 1)) / extent : 0.0;
  std::vector<std::uint64_t> code(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t c = 0;
    for (int d = 0; d < 3; ++d)
      c |= spread_bits(static_cast<std::uint64_t>((P(i, d) - lo(d)) * scale)) << d;
    code[i] = c;
  }
  std::stable_sort(order.begin(), order.end(),
                   [&code](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
  return order;
}

Matrix3 permute_rows(const Matrix3& M, const std::vector<std::uint32_t>& order) {
  Matrix3 out(M.rows(), 3);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < order.size(); ++k) out.row(k) = M.row(order[k]);
  return out;
}

Matrix3 unpermute_rows(const Matrix3& M, const std::vector<std::uint32_t>& order) {
  Matrix3 out(M.rows(), 3);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < order.size(); ++k) out.row(order[k]) = M.row(k);
  return out;
}

}  // namespace detexture
