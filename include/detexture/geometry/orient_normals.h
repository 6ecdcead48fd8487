// Consistent orientation of unoriented normals (Hoppe et al. 1992).
#pragma once

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct OrientNormalsResult {
  Normals normals;              ///< #P by 3, flipped where needed
  std::size_t components = 0;   ///< connected components of the neighbor graph
  std::size_t flipped = 0;      ///< normals whose sign was changed
};

/// Orient normals consistently: propagate the sign along a minimum spanning
/// tree of the neighbor graph N with edge cost 1 - |n_i . n_j| (Hoppe et al.
/// 1992). Each connected component is seeded at the point farthest from the
/// component's centroid, whose normal is turned to point away from the
/// centroid, so closed shapes end up facing outward.
/// Zero normals are left zero. Deterministic.
OrientNormalsResult orient_normals(const Positions& P, const Normals& normals,
                                   const Neighborhoods& N);

/// Fraction of neighbor pairs (i, j in N_i, j != i) whose normals point in
/// opposite directions (n_i . n_j < 0). Near 0 for consistent normals; a
/// cloud with a few flipped normals scores clearly above that.
double orientation_inconsistency(const Normals& normals, const Neighborhoods& N);

}  // namespace detexture
