// Neighborhoods that stay on one underlying surface, once texture is known.
//
// drop_opposite_neighbors.h splits R_i before texture detection, and only
// where two points are back to back, because the input normals are all it
// has: a test on the angle alone would also part a flat face from the steep
// flank of a bump on it, and the bump's points would then see no surface to
// be filtered and moved towards. Left in R_i are the neighbors past a bend
// that is not back to back: the rounded tip of a limb, an ear, horn or fin
// curling away, a convex rim seen from its side, the next part where two
// parts touch. The normal filters (Eqs. 1, 3) average them in, so small
// curved parts come out flattened and, where the other side dominates, a
// filtered normal turns round. Measured on bench/quality_real's bull with
// scales: 594 of 100,000 filtered normals ended more than 90° from their
// input normals, and the points moved along them were thrown off the surface
// (Dmax 2 × the input's).
//
// After detect_texture each point has a reference normal for "its" surface:
// its own normal if it is underlying surface, the normal of the surface
// fitted under it (TextureDetection::surface_normal, the base of a bump, not
// its flank) if it is texture. A pair (i, j) leaves both R_i and R_j when
// neither accepts the other: the angle between i's reference normal and j's
// normal, and between j's reference normal and i's normal, both exceed
// `max_angle_deg`. A flank point of a bump accepts the face under it, so the
// pair stays; two points on either side of a tip, or of a thin part, accept
// neither and part. The test is symmetric, so symmetric neighborhoods stay
// symmetric (the global update needs it).
//
// 60° was measured against 45-55° and against splitting every pair past the
// angle (`--sheet-any-pair`), on both quality suites (bench/RESULTS.md): at
// 60°, on the real shapes, normal error −8% on the bull, −6% on the spider,
// −5% on the engine, and no case of either suite worse by more than 0.3%;
// at 45-55° the real shapes gain more but the torus with waves loses 9-58%.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct DropNeighborsAcrossSurfacesParams {
  /// Largest angle between a point's reference normal and a neighbor's normal
  /// for the neighbor to count as on the point's surface, in degrees, in
  /// (0, 180]; 180 keeps every neighbor (the paper).
  double max_angle_deg = 60.0;
};

/// Remove from R (in place, order kept) every pair (i, j) neither of whose
/// points accepts the other (see above). N: #P by 3 point normals (unit,
/// oriented). surface_normals: #P by 3, detect_texture's surface_normal (unit,
/// signed like N; zero where no surface was fitted). is_texture: #P labels
/// (1 = texture). A pair with a zero normal among the ones compared is kept.
/// Returns the number of (i, j) entries removed. Throws std::invalid_argument
/// for an angle outside (0, 180] or a size mismatch.
std::size_t drop_neighbors_across_surfaces(Neighborhoods& R, const Normals& N,
                                           const Normals& surface_normals,
                                           const std::vector<std::uint8_t>& is_texture,
                                           const DropNeighborsAcrossSurfacesParams& params);

/// Check params; throws std::invalid_argument with a sentence.
void validate(const DropNeighborsAcrossSurfacesParams& params);

}  // namespace detexture
