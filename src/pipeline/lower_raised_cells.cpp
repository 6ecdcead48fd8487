#include "detexture/pipeline/lower_raised_cells.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const LowerRaisedCellsParams& p) {
  if (!(p.low_quantile >= 0.0 && p.low_quantile <= 1.0))
    throw std::invalid_argument("the quantile of the cells' feet (--cells-low-quantile) must lie "
                                "in [0, 1], got " +
                                number_text(p.low_quantile));
  if (!(p.spread_quantile >= 0.0 && p.spread_quantile <= 1.0))
    throw std::invalid_argument(
        "the quantile spread over the neighbors (--cells-spread-quantile) must lie in [0, 1], "
        "got " +
        number_text(p.spread_quantile));
  if (!(p.min_lean > 0.0 && p.min_lean <= 1.0))
    throw std::invalid_argument("lower_raised_cells: the lean must lie in (0, 1], got " +
                                number_text(p.min_lean));
  if (!(p.min_share >= 0.0 && p.min_share <= 1.0))
    throw std::invalid_argument("lower_raised_cells: the share must lie in [0, 1], got " +
                                number_text(p.min_share));
  if (!(p.max_depth >= 0.0) || !std::isfinite(p.max_depth))
    throw std::invalid_argument(
        "the deepest sink below the input (--cells-max-depth) must be a finite number >= 0, "
        "got " +
        number_text(p.max_depth));
  if (!(p.height >= 0.0) || !std::isfinite(p.height))
    throw std::invalid_argument("lower_raised_cells: the texture height must be >= 0, got " +
                                number_text(p.height));
  if (!(p.max_turn_deg > 0.0 && p.max_turn_deg <= 180.0))
    throw std::invalid_argument(
        "the largest turn of a normal that still sinks (--cells-max-turn) must lie in (0, 180] "
        "degrees, got " +
        number_text(p.max_turn_deg));
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("lower_raised_cells: the radius must be positive, got " +
                                number_text(p.radius));
}

namespace {

// The lower q-quantile of v (no interpolation), reordering v.
double quantile(std::vector<double>& v, double q) {
  const std::size_t k = static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Calls f(j) for every neighbor j of i within radius (i itself left out).
template <typename F>
void for_each_within(const Positions& P, const Neighborhoods& R, std::size_t i, double radius_sq,
                     F&& f) {
  for (const std::uint32_t* it = R.begin(i); it != R.end(i); ++it)
    if (*it != i && (P.row(*it) - P.row(i)).squaredNorm() <= radius_sq) f(*it);
}

// For every point, the q-quantile of value over itself and its neighbors
// within radius.
std::vector<double> neighborhood_quantile(const Positions& P, const Neighborhoods& R,
                                          const std::vector<double>& value, double radius_sq,
                                          double q) {
  const std::size_t n = value.size();
  std::vector<double> out(n);
#pragma omp parallel
  {
    std::vector<double> v;
#pragma omp for schedule(dynamic, 1024)
    for (std::size_t i = 0; i < n; ++i) {
      v.clear();
      v.push_back(value[i]);
      for_each_within(P, R, i, radius_sq, [&](std::uint32_t j) { v.push_back(value[j]); });
      out[i] = quantile(v, q);
    }
  }
  return out;
}

// For every point, the mean of value over itself and its neighbors within
// radius.
std::vector<double> neighborhood_mean(const Positions& P, const Neighborhoods& R,
                                      const std::vector<double>& value, double radius_sq) {
  const std::size_t n = value.size();
  std::vector<double> out(n);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    double sum = value[i];
    std::size_t count = 1;
    for_each_within(P, R, i, radius_sq, [&](std::uint32_t j) {
      sum += value[j];
      ++count;
    });
    out[i] = sum / static_cast<double>(count);
  }
  return out;
}

// For every point, the unit mean of its neighbors' normals within radius
// (itself left out); a zero row where they have none or cancel out.
Normals neighborhood_normal(const Positions& P, const Neighborhoods& R, const Normals& N,
                            double radius_sq) {
  const std::size_t n = static_cast<std::size_t>(P.rows());
  Normals out = Normals::Zero(P.rows(), 3);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for_each_within(P, R, i, radius_sq, [&](std::uint32_t j) { sum += N.row(j); });
    const double norm = sum.norm();
    if (norm > 0.0) out.row(static_cast<Eigen::Index>(i)) = sum / norm;
  }
  return out;
}

}  // namespace

LowerRaisedCellsResult lower_raised_cells(const Positions& P, const Positions& updated,
                                          const Normals& normals,
                                          const std::vector<std::uint8_t>& is_texture,
                                          double lean, const Neighborhoods& R,
                                          const LowerRaisedCellsParams& params) {
  validate(params);
  const std::size_t n = static_cast<std::size_t>(P.rows());
  if (updated.rows() != P.rows() || normals.rows() != P.rows() || is_texture.size() != n ||
      R.size() != n)
    throw std::invalid_argument(
        "lower_raised_cells: positions, normals, labels and neighborhoods differ in size");
  LowerRaisedCellsResult out;
  out.positions = updated;
  if (!params.enabled || n == 0) return out;
  std::size_t texture = 0;
  for (const std::uint8_t x : is_texture) texture += x != 0;
  if (!(lean <= -params.min_lean) ||
      !(static_cast<double>(texture) > params.min_share * static_cast<double>(n)))
    return out;
  out.applied = true;
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = (P.row(i) - updated.row(i)).dot(normals.row(i));
  const double radius_sq = params.radius * params.radius;
  const std::vector<double> a = neighborhood_quantile(P, R, t, radius_sq, params.low_quantile);
  const std::vector<double> b = neighborhood_quantile(P, R, a, radius_sq, params.spread_quantile);
  const std::vector<double> c = neighborhood_mean(P, R, b, radius_sq);
  const double depth = params.max_depth * params.height;
  const bool turn_test = params.max_turn_deg < 180.0;
  const Normals m = turn_test ? neighborhood_normal(P, R, normals, radius_sq) : Normals();
  const double min_cos = std::cos(params.max_turn_deg * M_PI / 180.0);
  std::size_t lowered = 0, limited = 0, turned = 0;
  for (std::size_t i = 0; i < n; ++i) {
    double sink = c[i];
    if (!(sink < 0.0) || !std::isfinite(sink)) continue;
    // Where the output normal turned over against its neighbors', their mean
    // says where down is; the depth limit is read along it too.
    Eigen::RowVector3d dir = normals.row(i);
    double ti = t[i];
    if (turn_test && m.row(i).squaredNorm() > 0.0 && !(normals.row(i).dot(m.row(i)) >= min_cos)) {
      dir = m.row(i);
      ti = (P.row(i) - updated.row(i)).dot(dir);
      ++turned;
    }
    if (depth > 0.0 && sink < ti - depth) {
      sink = ti - depth;
      ++limited;
      if (!(sink < 0.0)) continue;
    }
    out.positions.row(i) += sink * dir;
    ++lowered;
  }
  out.lowered = lowered;
  out.limited = limited;
  out.turned = turned;
  return out;
}

}  // namespace detexture
