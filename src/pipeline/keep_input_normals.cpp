#include "detexture/pipeline/keep_input_normals.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace detexture {

void validate(const KeepInputNormalsParams& p) {
  if (!(p.high >= 0.0) || !std::isfinite(p.high))
    throw std::invalid_argument(
        "the move up to which input normals are kept (--keep-input-high) must be >= 0, got " +
        number_text(p.high));
  if (p.high > 0.0 && !(p.low >= 0.0 && p.low < p.high))
    throw std::invalid_argument(
        "the move below which input normals are kept fully (--keep-input-low, " +
        number_text(p.low) + ") must be >= 0 and below --keep-input-high (" + number_text(p.high) +
        ")");
  if (!(p.radius > 0.0) || !std::isfinite(p.radius))
    throw std::invalid_argument("keep_input_normals: the radius must be positive, got " +
                                number_text(p.radius));
  if (!(p.lambda > 0.0) || !std::isfinite(p.lambda))
    throw std::invalid_argument("keep_input_normals: λ must be positive, got " +
                                number_text(p.lambda));
  if (!(p.exact_angle_deg >= 0.0 && p.exact_angle_deg < 90.0))
    throw std::invalid_argument(
        "the angle within which exact input normals are taken (--keep-input-exact-angle) must lie "
        "in [0, 90) degrees, got " +
        number_text(p.exact_angle_deg));
  if (!(p.exact_residual >= 0.0) || !std::isfinite(p.exact_residual))
    throw std::invalid_argument(
        "the residual under which input normals count as exact (--keep-input-exact-residual) "
        "must be >= 0, got " +
        number_text(p.exact_residual));
  if (!(p.still_angle_deg >= 0.0 && p.still_angle_deg < 90.0))
    throw std::invalid_argument(
        "the angle within which exact input normals are taken where the surface stayed "
        "(--keep-input-still-angle) must lie in [0, 90) degrees, got " +
        number_text(p.still_angle_deg));
  if (!(p.still_move >= 0.0) || !std::isfinite(p.still_move))
    throw std::invalid_argument(
        "the move under which the surface counts as stayed (--keep-input-still-move) must be "
        ">= 0, got " +
        number_text(p.still_move));
  if (!(p.still_move_engraved >= 0.0) || !std::isfinite(p.still_move_engraved))
    throw std::invalid_argument(
        "the move under which the surface counts as stayed where the relief is engraved "
        "(--keep-input-still-move-engraved) must be >= 0, got " +
        number_text(p.still_move_engraved));
  if (!(p.still_uniform_deg >= 0.0 && p.still_uniform_deg < 90.0))
    throw std::invalid_argument(
        "the angle within which the neighbors' input normals must agree "
        "(--keep-input-still-uniform) must lie in [0, 90) degrees, got " +
        number_text(p.still_uniform_deg));
  if (p.exact_neighbors < 3)
    throw std::invalid_argument(
        "the exactness test of input normals needs at least 3 neighbors, got " +
        number_text(p.exact_neighbors));
  if (p.facet_neighbors < 0)
    throw std::invalid_argument(
        "the number of neighbors the facet test of input normals reads "
        "(--keep-input-facet-neighbors) must be >= 0 (0: off), got " +
        number_text(p.facet_neighbors));
  if (p.facet_members < 3)
    throw std::invalid_argument(
        "the facet test of input normals needs at least 3 members "
        "(--keep-input-facet-members), got " +
        number_text(p.facet_members));
  if (!(p.facet_spread > 0.0 && p.facet_spread <= 1.0))
    throw std::invalid_argument(
        "the facet test's spread (KeepInputNormalsParams::facet_spread, Python "
        "keep_input_facet_spread) must lie in (0, 1], got " +
        number_text(p.facet_spread));
  if (!(p.facet_jump >= 1.0) || !std::isfinite(p.facet_jump))
    throw std::invalid_argument(
        "the facet test's jump (KeepInputNormalsParams::facet_jump, Python "
        "keep_input_facet_jump) must be >= 1, got " +
        number_text(p.facet_jump));
  if (!(p.still_reach >= 0.0 && p.still_reach < 1.0))
    throw std::invalid_argument(
        "the reach of the output normals where the surface stayed (--keep-input-still-reach) "
        "must lie in [0, 1), got " +
        number_text(p.still_reach));
  if (p.facet_transitional < 0)
    throw std::invalid_argument(
        "the facet test's transitional count (KeepInputNormalsParams::facet_transitional, "
        "Python keep_input_facet_transitional) must be >= 0, got " +
        number_text(p.facet_transitional));
  if (!(p.reached_angle_deg >= 0.0 && p.reached_angle_deg < 90.0))
    throw std::invalid_argument(
        "the angle within which exact input normals the output normals reach are taken "
        "(--keep-input-reached-angle) must lie in [0, 90) degrees (0: off), got " +
        number_text(p.reached_angle_deg));
  if (!(p.reached_share > 0.0 && p.reached_share < 1.0))
    throw std::invalid_argument(
        "the reach of the output normals (--keep-input-reached-share) must lie in (0, 1), got " +
        number_text(p.reached_share));
  if (p.facet_groups < 0 || p.facet_groups > kMaxFacetGroups)
    throw std::invalid_argument(
        "the facet test's number of other facets (--keep-input-facet-groups) must lie in [0, " +
        number_text(kMaxFacetGroups) + "] (0: off), got " + number_text(p.facet_groups));
}

KeepInputNormalsResult keep_input_normals(const Positions& P, const Positions& updated,
                                          const Normals& input_normals, const Normals& normals,
                                          const std::vector<std::uint8_t>& is_texture,
                                          const Neighborhoods& R,
                                          const KeepInputNormalsParams& params) {
  validate(params);
  const std::size_t n = R.size();
  if (static_cast<std::size_t>(P.rows()) != n || updated.rows() != P.rows() ||
      input_normals.rows() != P.rows() || normals.rows() != P.rows() ||
      (!is_texture.empty() && is_texture.size() != n))
    throw std::invalid_argument(
        "keep_input_normals: positions, normals, labels and neighborhoods differ in size");
  KeepInputNormalsResult out;
  out.normals = normals;
  const bool by_move = params.high > 0.0, by_exactness = params.exact_angle_deg > 0.0,
             by_stillness = params.still_angle_deg > 0.0,
             by_reach =
                 params.reached_angle_deg > 0.0 && (!params.engraved || params.reached_engraved);
  if (!by_move && !by_exactness && !by_stillness && !by_reach) return out;
  const double low = params.low * params.lambda, high = params.high * params.lambda;
  const double radius_sq = params.radius * params.radius;
  const double min_cos = std::cos(params.exact_angle_deg * M_PI / 180.0);
  const double max_residual = params.exact_residual * params.lambda;
  const double still_cos = std::cos(params.still_angle_deg * M_PI / 180.0);
  const double still_move =
      (params.engraved ? params.still_move_engraved : params.still_move) * params.lambda;
  const double uniform_cos = std::cos(params.still_uniform_deg * M_PI / 180.0);
  // m_i is read up to the larger of the two bounds it is compared with.
  const double move_bound = std::max(by_move ? high : 0.0, by_stillness ? still_move : 0.0);
  std::vector<double> moved(by_move || by_stillness ? n : 0);
  for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = (updated.row(i) - P.row(i)).norm();
  // ñ_i is exact where its k nearest neighbors lie in its tangent plane.
  const auto exact = [&](std::size_t i, const Eigen::RowVector3d& unit_given) {
    double sum = 0.0;
    int count = 0;
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i) && count < params.exact_neighbors;
         ++nb) {
      if (*nb == i) continue;
      sum += std::abs(unit_given.dot(P.row(*nb) - P.row(i)));
      ++count;
    }
    return count >= 3 && sum <= max_residual * count;
  };
  // ñ_i is a flat facet's, read past its edges (F_i in the header).
  // Angles are unsigned (|cos|), so at c φ >= 90° every non-member counts.
  const double jump_angle = params.facet_jump * params.still_uniform_deg;
  const double jump_cos = jump_angle >= 90.0 ? 0.0 : std::cos(jump_angle * M_PI / 180.0);
  const int facet_neighbors =
      params.facet_neighbors == 0 ? 0 : std::max(params.facet_neighbors, params.exact_neighbors);
  const auto flat_facet = [&](std::size_t i, const Eigen::RowVector3d& unit_given) {
    if (facet_neighbors == 0) return false;
    // The other facets the transitional neighbors lie on, while there are
    // at most g of them: each one's first input normal and point (the
    // others within φ of that normal), and how far its points lie off that
    // plane in all.
    struct OtherFacet {
      Eigen::RowVector3d normal, at;
      double off = 0.0;
      int size = 0;
    };
    std::array<OtherFacet, kMaxFacetGroups> other;
    int looked = 0, members = 0, transitional = 0, groups = 0;
    double sum = 0.0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i) && looked < facet_neighbors; ++nb) {
      if (*nb == i) continue;
      ++looked;
      const Eigen::RowVector3d g = input_normals.row(*nb);
      const double norm = g.norm();
      if (!(norm > 0.0)) continue;
      const double c = std::abs(g.dot(unit_given));
      if (c < uniform_cos * norm) {
        if (c < jump_cos * norm) continue;  // past an edge's jump
        ++transitional;
        if (groups <= params.facet_groups) {
          const Eigen::RowVector3d unit = g / norm;
          auto facet = other.begin(), last = other.begin() + groups;
          while (facet != last && std::abs(unit.dot(facet->normal)) < uniform_cos) ++facet;
          if (facet != last) {
            facet->off += std::abs(facet->normal.dot(P.row(*nb) - facet->at));
            ++facet->size;
          } else if (groups++ < params.facet_groups) {
            *facet = {unit, P.row(*nb), 0.0, 1};
          }
        }
        if (transitional > params.facet_transitional && groups > params.facet_groups) return false;
        continue;
      }
      const Eigen::Vector3d d = (P.row(*nb) - P.row(i)).transpose();
      sum += std::abs(unit_given.dot(d.transpose()));
      mean += d;
      second += d * d.transpose();
      ++members;
    }
    if (members < params.facet_members || sum > max_residual * members) return false;
    // The other facets are flat too: their points lie in the plane of their
    // normal, as the far side of an edge does and noisy or alternating
    // normals over one plane do not.
    if (transitional > params.facet_transitional)
      for (auto facet = other.begin(); facet != other.begin() + groups; ++facet)
        if (facet->off > max_residual * facet->size) return false;
    mean /= members;
    const Eigen::Matrix3d cov = second / members - mean * mean.transpose();
    const Eigen::Vector3d spread =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
    return spread(2) > 0.0 && spread(1) >= params.facet_spread * spread(2);
  };
  // ñ_i's angle to n'_i (cosine tilt_cos) is no larger than n' turns within
  // ρ (the cone).
  const auto cone = [&](std::size_t i, const Eigen::RowVector3d& unit_output, double tilt_cos) {
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
      if ((P.row(*nb) - P.row(i)).squaredNorm() > radius_sq) continue;
      const Eigen::RowVector3d o = normals.row(*nb);
      const double norm = o.norm();
      if (norm > 0.0 && std::abs(o.dot(unit_output)) <= tilt_cos * norm) return true;
    }
    return false;
  };
  // Some n'_j within ρ (or n'_i) lies within α times ñ_i's tilt (angle
  // tilt) of ñ_i (the reach).
  const auto reach = [&](std::size_t i, const Eigen::RowVector3d& unit_given, double tilt) {
    const double reach_cos = std::cos(params.still_reach * tilt);
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
      if ((P.row(*nb) - P.row(i)).squaredNorm() > radius_sq) continue;
      const Eigen::RowVector3d o = normals.row(*nb);
      const double norm = o.norm();
      if (norm > 0.0 && std::abs(o.dot(unit_given)) >= reach_cos * norm) return true;
    }
    return false;
  };
  // Nothing of ñ_i's facet within ρ (input normals within φ of it) moved by
  // more than μ λ.
  const auto facet_stayed = [&](std::size_t i, const Eigen::RowVector3d& unit_given) {
    if (moved[i] > still_move) return false;
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i); ++nb) {
      if (moved[*nb] <= still_move || (P.row(*nb) - P.row(i)).squaredNorm() > radius_sq) continue;
      const Eigen::RowVector3d g = input_normals.row(*nb);
      const double norm = g.norm();
      if (norm > 0.0 && std::abs(g.dot(unit_given)) >= uniform_cos * norm) return false;
    }
    return true;
  };
  // The surface stayed around p_i and ñ_i is a facet's (see the header):
  // its nearest neighbors' input normals agree with it.
  const auto uniform = [&](std::size_t i, const Eigen::RowVector3d& unit_given) {
    int count = 0;
    for (const std::uint32_t* nb = R.begin(i); nb != R.end(i) && count < params.exact_neighbors;
         ++nb) {
      if (*nb == i) continue;
      const Eigen::RowVector3d g = input_normals.row(*nb);
      const double norm = g.norm();
      if (!(norm > 0.0) || std::abs(g.dot(unit_given)) < uniform_cos * norm) return false;
      ++count;
    }
    return true;
  };
  // Points the tests below took (fully or in part), for the reach after them.
  std::vector<std::uint8_t> taken(n, 0);
  std::size_t kept = 0, exact_kept = 0, still_kept = 0, facet_kept = 0, texture_kept = 0;
#pragma omp parallel for schedule(dynamic, 256) \
    reduction(+ : kept, exact_kept, still_kept, facet_kept, texture_kept)
  for (std::size_t i = 0; i < n; ++i) {
    const bool texture = !is_texture.empty() && is_texture[i];
    if (texture && !params.texture_facets) continue;
    const Eigen::RowVector3d given = input_normals.row(i);
    const Eigen::RowVector3d ni = normals.row(i);
    if (given.squaredNorm() == 0.0 || !given.allFinite() || ni.squaredNorm() == 0.0) continue;
    double w = 0.0, m = 0.0;
    if (by_move || by_stillness) {
      m = moved[i];
      for (const std::uint32_t* nb = R.begin(i); nb != R.end(i) && m <= move_bound; ++nb)
        if ((P.row(*nb) - P.row(i)).squaredNorm() <= radius_sq) m = std::max(m, moved[*nb]);
    }
    if (by_move && !texture) w = std::clamp((high - m) / (high - low), 0.0, 1.0);
    if (w < 1.0 && (by_exactness || by_stillness)) {
      const Eigen::RowVector3d unit_given = given.normalized();
      const Eigen::RowVector3d unit_output = ni.normalized();
      const double c = std::abs(unit_given.dot(unit_output));
      const bool close = by_exactness && c >= min_cos;
      const bool still =
          !close && by_stillness && c >= still_cos &&
          (m <= still_move || (params.still_facet_move && facet_stayed(i, unit_given)));
      if (close || still) {
        // The nearest neighbors read as one plane (with agreeing normals
        // where the surface stayed or the point is texture), or the facet
        // found past its edges; where the surface stayed, the reach (or the
        // cone) as well.
        const bool plain = exact(i, unit_given) && ((close && !texture) || uniform(i, unit_given));
        const bool found = !plain && flat_facet(i, unit_given);
        const auto around = [&] {
          return params.still_reach > 0.0 ? reach(i, unit_given, std::acos(std::min(1.0, c)))
                                          : cone(i, unit_output, c);
        };
        if ((plain || found) && (close || around())) {
          w = 1.0;
          ++exact_kept;
          still_kept += still;
          facet_kept += found;
          texture_kept += texture;
        }
      }
    }
    if (w == 0.0) continue;
    const Eigen::RowVector3d signed_given =
        (given.dot(ni) < 0.0 ? Eigen::RowVector3d(-given) : given).normalized();
    const Eigen::RowVector3d mixed = w * signed_given + (1.0 - w) * ni;
    const double norm = mixed.norm();
    if (!(norm > 0.0)) continue;
    out.normals.row(i) = mixed / norm;
    taken[i] = 1;
    ++kept;
  }
  // The exact input normals the output normals reach (see the header),
  // read from the normals above so that a facet partly taken reaches the
  // rest of it, and written apart so that no point reads another's result.
  std::size_t reached = 0;
  if (by_reach) {
    const Normals first = out.normals;
    const double reached_cos = std::cos(params.reached_angle_deg * M_PI / 180.0);
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : reached)
    for (std::size_t i = 0; i < n; ++i) {
      const bool texture = !is_texture.empty() && is_texture[i];
      if (taken[i] || (texture && !params.texture_facets)) continue;
      const Eigen::RowVector3d given = input_normals.row(i);
      const Eigen::RowVector3d ni = normals.row(i);
      if (given.squaredNorm() == 0.0 || !given.allFinite() || ni.squaredNorm() == 0.0) continue;
      const Eigen::RowVector3d unit_given = given.normalized();
      const double c = std::abs(unit_given.dot(ni.normalized()));
      if (c < reached_cos || !exact(i, unit_given)) continue;
      const double reach_cos = std::cos(params.reached_share * std::acos(std::min(1.0, c)));
      bool reaches = false;
      for (const std::uint32_t* nb = R.begin(i); nb != R.end(i) && !reaches; ++nb) {
        if (*nb == i || (P.row(*nb) - P.row(i)).squaredNorm() > radius_sq) continue;
        const Eigen::RowVector3d o = first.row(*nb);
        const double norm = o.norm();
        reaches = norm > 0.0 && std::abs(o.dot(unit_given)) >= reach_cos * norm;
      }
      if (!reaches) continue;
      out.normals.row(i) = given.dot(ni) < 0.0 ? Eigen::RowVector3d(-unit_given) : unit_given;
      ++reached;
    }
  }
  kept += reached;
  out.reached = reached;
  out.kept = kept;
  out.exact = exact_kept;
  out.still = still_kept;
  out.facets = facet_kept;
  out.texture = texture_kept;
  return out;
}

}  // namespace detexture
