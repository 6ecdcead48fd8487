#include "detexture/eval/compare_to_ground_truth.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>
#include "detexture/geometry/point_index.h"

namespace detexture {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// For each row of Q, the index of the nearest row of P and the distance.
void nearest_in(const Positions& P, const Positions& Q, std::vector<std::uint32_t>& index,
                std::vector<double>& distance) {
  const PointIndex tree(P);
  const Eigen::Index n = Q.rows();
  index.resize(static_cast<std::size_t>(n));
  distance.resize(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    const double q[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
    double distance_sq = 0.0;
    const std::uint32_t j = tree.nearest(q, &distance_sq);
    index[static_cast<std::size_t>(i)] = j;
    distance[static_cast<std::size_t>(i)] = std::sqrt(distance_sq);
  }
}

struct MeanStd {
  double mean = 0.0, std = 0.0;
};

// Compensated (Neumaier) sum in index order: exact to rounding for a few
// million terms, and independent of the thread count.
double accurate_sum(const std::vector<double>& v) {
  double sum = 0.0, compensation = 0.0;
  for (double x : v) {
    const double t = sum + x;
    compensation += std::abs(sum) >= std::abs(x) ? (sum - t) + x : (x - t) + sum;
    sum = t;
  }
  return sum + compensation;
}

// Two-pass population statistics (the variance divides by the count).
MeanStd mean_std(const std::vector<double>& v) {
  MeanStd s;
  if (v.empty()) return s;
  const double n = static_cast<double>(v.size());
  s.mean = accurate_sum(v) / n;
  std::vector<double> deviation_sq(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) deviation_sq[i] = (v[i] - s.mean) * (v[i] - s.mean);
  s.std = std::sqrt(accurate_sum(deviation_sq) / n);
  return s;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

GroundTruthComparison compare_to_ground_truth(const Positions& R, const Normals& RN,
                                              const Positions& G, const Normals& GN) {
  if (R.rows() == 0) throw std::invalid_argument("the result has no points to compare");
  if (G.rows() == 0) throw std::invalid_argument("the ground truth has no points to compare with");
  if (GN.rows() != G.rows())
    throw std::invalid_argument(
        "the ground truth needs a normal for every point (point-to-plane distances use them)");
  if (RN.rows() != 0 && RN.rows() != R.rows())
    throw std::invalid_argument("the result has normals for some points but not all");

  GroundTruthComparison c;
  c.result_points = static_cast<std::size_t>(R.rows());
  c.ground_truth_points = static_cast<std::size_t>(G.rows());
  c.diagonal = bounding_box_diagonal(G);
  c.has_normals = RN.rows() == R.rows();

  std::vector<std::uint32_t> nearest;
  std::vector<double> unused;
  nearest_in(G, R, nearest, unused);
  const std::size_t n = c.result_points;
  std::vector<double> signed_distance(n), distance(n), angle(n, -1.0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Index r = static_cast<Eigen::Index>(i), g = nearest[i];
    signed_distance[i] = (R.row(r) - G.row(g)).dot(GN.row(g));
    distance[i] = std::abs(signed_distance[i]);
    if (c.has_normals && RN.row(r).squaredNorm() > 0.0) {
      // atan2 of |cross| and dot is accurate at small angles, where acos is not.
      const Eigen::Vector3d a = RN.row(r).transpose(), b = GN.row(g).transpose();
      angle[i] = std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / kPi;
    }
  }
  const MeanStd unsigned_stats = mean_std(distance), signed_stats = mean_std(signed_distance);
  c.max_distance = *std::max_element(distance.begin(), distance.end());
  c.mean_distance = unsigned_stats.mean;
  c.std_distance = unsigned_stats.std;
  c.mean_signed_distance = signed_stats.mean;
  c.std_signed_distance = signed_stats.std;

  if (c.has_normals) {
    std::vector<double> valid;
    std::size_t within = 0;
    for (double a : angle) {
      if (a < 0.0) continue;
      valid.push_back(a);
      if (a <= 10.0) ++within;
    }
    c.zero_normals = n - valid.size();
    c.mean_angle_degrees = mean_std(valid).mean;
    c.within_10_degrees_percent =
        valid.empty() ? 0.0
                      : 100.0 * static_cast<double>(within) / static_cast<double>(valid.size());
  }

  std::vector<std::uint32_t> unused_index;
  std::vector<double> coverage;
  nearest_in(R, G, unused_index, coverage);
  c.mean_coverage_distance = mean_std(coverage).mean;
  c.max_coverage_distance = *std::max_element(coverage.begin(), coverage.end());
  return c;
}

std::string comparison_to_json(const GroundTruthComparison& c) {
  const double d = c.diagonal > 0.0 ? c.diagonal : 1.0;
  auto rel = [&](double v) { return number(c.diagonal > 0.0 ? v / d : 0.0); };
  std::string s = "{\n";
  auto add = [&](const char* key, const std::string& value, bool last = false) {
    s += std::string("  \"") + key + "\": " + value + (last ? "\n" : ",\n");
  };
  add("result_points", std::to_string(c.result_points));
  add("ground_truth_points", std::to_string(c.ground_truth_points));
  add("diagonal", number(c.diagonal));
  add("dmax", number(c.max_distance));
  add("dmean", number(c.mean_distance));
  add("dstd", number(c.std_distance));
  add("dmax_relative", rel(c.max_distance));
  add("dmean_relative", rel(c.mean_distance));
  add("dstd_relative", rel(c.std_distance));
  add("signed_mean", number(c.mean_signed_distance));
  add("signed_std", number(c.std_signed_distance));
  add("signed_mean_relative", rel(c.mean_signed_distance));
  add("signed_std_relative", rel(c.std_signed_distance));
  add("normal_angle_mean_degrees", c.has_normals ? number(c.mean_angle_degrees) : "null");
  add("normals_within_10_degrees_percent",
      c.has_normals ? number(c.within_10_degrees_percent) : "null");
  add("zero_normals", std::to_string(c.zero_normals));
  add("coverage_mean", number(c.mean_coverage_distance));
  add("coverage_max", number(c.max_coverage_distance));
  add("coverage_mean_relative", rel(c.mean_coverage_distance));
  add("coverage_max_relative", rel(c.max_coverage_distance), true);
  return s + "}\n";
}

std::string comparison_to_table(const GroundTruthComparison& c) {
  std::string s;
  char line[160];
  auto row = [&](const char* name, double v) {
    if (c.diagonal > 0.0)
      std::snprintf(line, sizeof line, "%-34s %14.6g %14.6g\n", name, v, v / c.diagonal);
    else
      std::snprintf(line, sizeof line, "%-34s %14.6g %14s\n", name, v, "-");
    s += line;
  };
  std::snprintf(line, sizeof line, "result points %zu, ground-truth points %zu, diagonal %.6g\n",
                c.result_points, c.ground_truth_points, c.diagonal);
  s += line;
  std::snprintf(line, sizeof line, "%-34s %14s %14s\n", "metric", "absolute", "/ diagonal");
  s += line;
  row("Dmax (max distance)", c.max_distance);
  row("Dmean (mean distance)", c.mean_distance);
  row("sigma (std of distance)", c.std_distance);
  row("signed mean (uniform shift)", c.mean_signed_distance);
  row("signed std (residual texture)", c.std_signed_distance);
  row("coverage mean (GT -> result)", c.mean_coverage_distance);
  row("coverage max (GT -> result)", c.max_coverage_distance);
  if (c.has_normals) {
    std::snprintf(line, sizeof line, "%-34s %14.6g\n%-34s %14.6g\n", "normal angle mean (degrees)",
                  c.mean_angle_degrees, "normals within 10 degrees (%)",
                  c.within_10_degrees_percent);
    s += line;
    if (c.zero_normals > 0) {
      std::snprintf(line, sizeof line, "%-34s %14zu\n", "zero normals (left out)", c.zero_normals);
      s += line;
    }
  } else {
    std::snprintf(line, sizeof line, "%-34s %14s\n%-34s %14s\n", "normal angle mean (degrees)",
                  "n/a", "normals within 10 degrees (%)", "n/a");
    s += line;
  }
  return s;
}

}  // namespace detexture
