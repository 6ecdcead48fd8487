#include "detexture/pipeline/repair_folds.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace detexture {
namespace {

Eigen::Vector3d unit_normal(const Positions& P, const TriangleIndices& T, Eigen::Index t) {
  const Eigen::Vector3d a = P.row(T(t, 0)).transpose();
  const Eigen::Vector3d n = (P.row(T(t, 1)).transpose() - a).cross(P.row(T(t, 2)).transpose() - a);
  const double norm = n.norm();
  return norm > 0.0 ? Eigen::Vector3d(n / norm) : Eigen::Vector3d::Zero();
}

}  // namespace

Positions repair_folds(const Positions& input, const Positions& output, const TriangleIndices& T,
                       const RepairFoldsParams& params, RepairFoldsReport* report) {
  if (!(params.fold_angle_deg > 0.0 && params.fold_angle_deg < 180.0))
    throw std::invalid_argument("the fold angle must be in (0, 180) degrees, got " +
                                number_text(params.fold_angle_deg));
  if (!(params.least_limit_deg >= 0.0 && params.least_limit_deg <= params.fold_angle_deg))
    throw std::invalid_argument("the least dihedral limit must be in [0, the fold angle], got " +
                                number_text(params.least_limit_deg));
  if (input.rows() != output.rows())
    throw std::invalid_argument("repair_folds needs as many output positions as input positions");
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int c = 0; c < 3; ++c)
      if (T(t, c) < 0 || T(t, c) >= input.rows())
        throw std::invalid_argument("triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(T(t, c)) + " of " +
                                    std::to_string(input.rows()));
  RepairFoldsReport local;
  RepairFoldsReport& rep = report ? *report : local;
  rep = RepairFoldsReport{};
  rep.input = measure_folds(input, T, input, params.fold_angle_deg);
  rep.update = measure_folds(output, T, input, params.fold_angle_deg);
  if (!params.enabled) {
    rep.output = rep.update;
    return output;
  }
  const InteriorEdges edges = interior_edges(T);
  const std::vector<double> before = dihedral_angles_deg(input, T, edges);
  const double floor_deg =
      std::min(params.fold_angle_deg, std::max(rep.input.p99_dihedral_deg, params.least_limit_deg));
  std::vector<double> limit(before.size());
  for (std::size_t e = 0; e < before.size(); ++e) limit[e] = std::max(before[e], floor_deg) + 1e-9;
  std::vector<Eigen::Vector3d> input_normal(static_cast<std::size_t>(T.rows()));
  for (Eigen::Index t = 0; t < T.rows(); ++t) input_normal[t] = unit_normal(input, T, t);

  const Positions move = output - input;
  std::vector<double> keep(static_cast<std::size_t>(input.rows()), 1.0);  // share of the move
  std::vector<std::uint8_t> bad_vertex(keep.size());
  std::vector<std::uint8_t> held(keep.size(), 0);
  Positions Q = output;
  for (;;) {
    std::fill(bad_vertex.begin(), bad_vertex.end(), 0);
    bool any = false;
    auto mark = [&](Eigen::Index t) {
      for (int c = 0; c < 3; ++c) bad_vertex[static_cast<std::size_t>(T(t, c))] = 1;
      any = true;
    };
    const std::vector<double> now = dihedral_angles_deg(Q, T, edges);
    for (std::size_t e = 0; e < now.size(); ++e)
      if (now[e] > limit[e]) {
        mark(edges.left[e]);
        mark(edges.right[e]);
      }
    std::vector<std::uint8_t> flipped(static_cast<std::size_t>(T.rows()));
#pragma omp parallel for schedule(static)
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      flipped[t] = unit_normal(Q, T, t).dot(input_normal[t]) < 0.0;
    for (Eigen::Index t = 0; t < T.rows(); ++t)
      if (flipped[t]) mark(t);
    if (!any) break;
    ++rep.rounds;
    for (std::size_t i = 0; i < keep.size(); ++i) {
      if (!bad_vertex[i] || keep[i] == 0.0) continue;
      keep[i] = keep[i] > 1.0 / 32 ? 0.5 * keep[i] : 0.0;  // 6 halvings, then none
      held[i] = 1;
      const auto r = static_cast<Eigen::Index>(i);
      Q.row(r) = input.row(r) + keep[i] * move.row(r);
    }
  }
  for (std::uint8_t h : held) rep.vertices_held += h;
  rep.output = measure_folds(Q, T, input, params.fold_angle_deg);
  return Q;
}

}  // namespace detexture
