// Normals by principal component analysis over each point's neighborhood.
#pragma once

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct EstimateNormalsResult {
  Normals normals;            ///< #P by 3 unit normals, sign arbitrary (see orient_normals)
  Eigen::VectorXd variation;  ///< #P surface variation λ0/(λ0+λ1+λ2), in [0, 1/3]
  std::size_t degenerate = 0; ///< points with < 3 neighbors or collinear neighbors
};

/// PCA normal of every point: the eigenvector of the smallest eigenvalue of
/// the covariance of its neighbors. Degenerate points (fewer than three
/// neighbors, or all collinear) get a zero normal and are counted; callers
/// decide what to do with them (orient_normals gives them their neighbors').
EstimateNormalsResult estimate_normals(const Positions& P, const Neighborhoods& N,
                                       const ProgressFn& progress = {});

}  // namespace detexture
