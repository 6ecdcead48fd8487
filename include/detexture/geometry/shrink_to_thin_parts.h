// Neighborhoods no wider than the thin parts they sit on.
//
// One r serves the whole cloud, but real shapes have parts thinner than the
// texture is wide: fingers, legs, horns, tails. On a limb of radius ρ < r,
// R_i wraps around it: drop_opposite_neighbors.h takes away the back, but
// what stays is a strip bent through ±60° about the limb, which no plane or
// quadric of Eq. 2 follows, so the limb is labelled texture, its normals are
// averaged around it and the update flattens it (the person's fingers, the
// spider's legs ended about 25° off in normal, against 4-5° elsewhere).
//
// So each point's neighborhood radius r_i shrinks to the distance of the
// nearest neighbor that is the back of the part it lies on — behind p_i's
// tangent plane, with p_i behind its own, and normals more than
// `back_angle_deg` apart (the test of drop_opposite_neighbors, at a wider
// angle, so that creases are left alone) — but not below
// `min_radius_fraction` × r. A back straight through the part (within
// `plate_angle_deg` of either normal) is the back of a plate or a wall:
// drop_opposite_neighbors already keeps each side of a plate to itself and
// the side is flat, so R_i stays whole there (shrinking there cost a
// textured plate its bumps, and the engine block 9% in residual texture).
// A pair (i, j) stays when |p_i − p_j| ≤ min(r_i, r_j), so symmetric
// neighborhoods stay symmetric. Points with no such back within r keep R_i
// whole: on bench/quality's shapes (creases of 63-117°, no thin part) and
// the organic synth shapes nothing changes (the pyramid moves by 0.3%).
// Measured on bench/quality_real's meshes (hand-set r, bench/RESULTS.md):
// residual texture 5-11% lower on the bull, the person, the duck and the
// spider, normal error 0.5-8% lower; the engine block 4.4% higher in
// residual texture and 0.9% in normal error. The floor 0.5 was measured
// against 0.3 (the person gained more, the engine lost 5% in normal error)
// and 0.7 (less gain everywhere).
#pragma once

#include <cstddef>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct ShrinkToThinPartsParams {
  /// r of the neighborhoods, in the cloud's units; > 0. remove_texture fills it.
  double radius = 0.0;
  /// Least r_i, as a fraction of r, in (0, 1]; 1 keeps every R_i whole (the
  /// paper).
  double min_radius_fraction = 0.5;
  /// Least angle between the normals of a point and of a neighbor behind it
  /// for the neighbor to be the back of a thin part, in degrees, in (90, 180).
  double back_angle_deg = 120.0;
  /// A nearest back that lies within this angle of straight through the
  /// part along either point's normal, in degrees, in [0, 90), is the back
  /// of a plate or a wall, not of a limb (on a limb the first back is about
  /// 30° off straight through): R_i stays whole there, since
  /// drop_opposite_neighbors.h already keeps each side of a plate to itself
  /// and the side is flat. 0 shrinks at plates too.
  double plate_angle_deg = 15.0;
};

struct ShrinkToThinPartsResult {
  std::size_t points = 0;   ///< points whose radius r_i was cut below r
  std::size_t removed = 0;  ///< (i, j) entries removed from R
};

/// Cut every row of R (radius neighborhoods of P, rows sorted by distance)
/// in place to the members within min(r_i, r_j) of p_i, order kept. N
/// (#P by 3) are consistently oriented unit normals; pairs with a zero normal
/// never mark a back. Throws std::invalid_argument for parameters out of
/// range or a size mismatch.
ShrinkToThinPartsResult shrink_to_thin_parts(Neighborhoods& R, const Positions& P, const Normals& N,
                                             const ShrinkToThinPartsParams& params);

/// Check params; throws std::invalid_argument with a sentence.
void validate(const ShrinkToThinPartsParams& params);

}  // namespace detexture
