// Normals by principal component analysis over each point's neighborhood.
#pragma once

#include <cstddef>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// A neighborhood is treated as collinear (or coincident), and its normal as
/// undetermined, when its spread along the second principal axis is at most
/// this fraction of its spread along the first: sqrt(λ1) <= 1e-5 sqrt(λ2).
/// Why 1e-5: rounding in the 3x3 eigensolver perturbs the smallest
/// eigenvector by about ε λ2/λ1 (ε = 2.2e-16), i.e. at most ~2e-6 rad at this
/// ratio; beyond it the "normal" would be rounding noise. Exactly coincident
/// neighbors (λ2 = 0) are caught by the same test.
constexpr double kMinSpreadRatio = 1e-5;

struct EstimateNormalsResult {
  Normals
      normals;  ///< #P by 3 unit normals, sign arbitrary (see orient_normals); zero if degenerate
  Eigen::VectorXd variation;  ///< #P surface variation λ0/(λ0+λ1+λ2), in [0, 1/3]; 0 if all λ are 0
  std::size_t degenerate = 0;  ///< points with < 3 neighbors, or collinear/coincident neighbors
};

/// PCA normal of every point: the eigenvector of the smallest eigenvalue λ0
/// of the covariance of its neighbors N_i (self included), with
/// λ0 <= λ1 <= λ2.
///
/// Degenerate points (fewer than three neighbors, or neighbors that are
/// collinear or coincident, see kMinSpreadRatio) get a zero normal and are
/// counted: no direction is invented for them. orient_normals leaves zero
/// normals zero; reestimate_zero_normals retries them with other
/// neighborhoods.
///
/// Accuracy: the covariance is formed from p_j - p_i (exact for nearby
/// points, so far-from-origin clouds lose nothing) in two passes around the
/// mean, and decomposed with Eigen's iterative SelfAdjointEigenSolver. The
/// closed-form computeDirect was measured to be wrong by up to 90 degrees on
/// exactly planar but elongated neighborhoods (second axis 1e-4 of the
/// first), where the iterative solver is within 2e-8 rad. A noise-free plane
/// gives the plane normal to about 1e-15.
///
/// P  #P by 3 positions
/// N  neighborhoods of P (radius or k-NN), N.size() == #P
/// progress  called with the fraction done, from one thread at a time
/// Throws std::invalid_argument if N does not match P.
EstimateNormalsResult estimate_normals(const Positions& P, const Neighborhoods& N,
                                       const ProgressFn& progress = {});

/// Fill in the zero-length normals of an oriented normal field (the PLY
/// reader leaves missing or zero normals as (0,0,0) and counts them).
///
/// Each zero normal gets the PCA normal of its neighborhood N_i (same
/// computation as estimate_normals), signed to agree with the sum of the
/// non-zero input normals of its neighbors. A zero normal stays zero when its
/// PCA is degenerate, or when its neighbors give no orientation (they are all
/// zero too, or their sum is perpendicular to the PCA normal): the number
/// still zero is (zero normals in) - *reestimated. Non-zero normals are
/// returned unchanged. Only input normals are used as references, so the
/// result does not depend on the order in which points are processed.
///
/// P  #P by 3 positions
/// normals  #P by 3 normals, some of them (0,0,0)
/// N  neighborhoods of P, N.size() == #P
/// reestimated  if not null, receives the number of zero normals replaced
/// Throws std::invalid_argument if the sizes do not match.
Normals reestimate_zero_normals(const Positions& P, const Normals& normals, const Neighborhoods& N,
                                std::size_t* reestimated = nullptr);

}  // namespace detexture
