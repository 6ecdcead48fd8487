// Neighborhoods that stay on their own sheet of a thin part.
//
// A radius neighborhood R_i of a point on a thin part (a fin, an ear, a
// finger, a plate, two strands of a tube passing close) reaches through to
// the other side once the part is thinner than 2r. Those neighbors lie on a
// different sheet of the surface, their normals point the other way, and
// every stage that mixes them in is wrong: RANSAC fits a plane between the
// sheets (Eq. 2), the Gaussian and rolling filters (Eqs. 1, 3) average
// opposite normals, and the position update pulls the sheets together. The
// paper's shapes are exactly such parts; measured on them before this stage,
// points near the other side ended about twice as far off in normal as the
// rest.
//
// So a neighbor j is dropped from R_i when the two are back to back — each
// lies behind the other's tangent plane, as across the material of a thin
// part — and their normals make more than `max_angle`. The test is
// symmetric, so symmetric neighborhoods stay symmetric. It needs oriented
// normals (the input's, or the estimated and oriented ones). Points facing
// each other across a gap or a concave crease (groove walls, the inside of
// a bend) are never back to back and stay. Convex creases sharper than
// 180° − max_angle are split too, which is what a normal filter wants: each
// face then sees only itself, and the crease stays sharp (bench/quality's
// cube with bumps: 1.65° → 1.03° mean normal error, pyramid 3.72° → 3.30°).
// Back-to-back points on one textured sheet (the two flanks of a convex
// bump) are texture, which the filters leave out anyway. 60° was measured
// against 120° and 40° on both quality suites: 40° gained on thin legs and
// scales but lost 24% on the torus with waves (bench/RESULTS.md).
#pragma once

#include <cstddef>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct DropOppositeNeighborsParams {
  /// Largest angle between n_i and a neighbor's normal for the neighbor to
  /// stay in R_i, in degrees, in (0, 180]; 180 keeps every neighbor (the paper).
  double max_angle_deg = 60.0;
  /// Drop only pairs that are also back to back: each behind the other's
  /// tangent plane, as across the material of a thin part (see above).
  bool back_to_back_only = true;
};

/// Whether a neighbor at offset d = p_j − p_i, with normal n_j, is the back of
/// the part p_i (normal n_i) lies on: back to back (each behind the other's
/// tangent plane) with n_i·n_j below `max_cos`. The test of this stage, of
/// shrink_to_thin_parts.h and of estimate_texture_scale's thin radius.
inline bool is_back_of_part(const Eigen::RowVector3d& ni, const Eigen::RowVector3d& nj,
                            const Eigen::RowVector3d& d, double max_cos) {
  return ni.dot(nj) < max_cos && d.dot(ni) < 0.0 && d.dot(nj) > 0.0;
}

/// Remove from every row of R (in place, order kept) the neighbors whose
/// normal in N (#P by 3, unit or zero) makes more than params.max_angle_deg
/// with the row point's normal. Pairs with a zero normal are kept (nothing
/// to judge by). Returns the number of (i, j) entries removed. Throws
/// std::invalid_argument for an angle outside (0, 180] or a size mismatch.
std::size_t drop_opposite_neighbors(Neighborhoods& R, const Positions& P, const Normals& N,
                                    const DropOppositeNeighborsParams& params);

/// Check params; throws std::invalid_argument with a sentence.
void validate(const DropOppositeNeighborsParams& params);

}  // namespace detexture
