// Mean curvature C(p_i) used by the guidance normals (Sun et al. 2019, Eqs. 4
// and 8). The paper does not say how C is estimated; we take it from the
// current normal field, which is what the guidance is about:
//
//   κ_ij = (n_i - n_j)·(p_i - p_j) / |p_i - p_j|²    (normal curvature along p_j - p_i)
//   C_i  = | mean_{j∈R_i, j≠i} κ_ij |
//
// The mean of normal curvatures over directions spread evenly around p_i is
// the mean curvature H (Euler), so C_i ≈ |H|: 1/R on a sphere of radius R, 0
// on a plane, large across a crease. It needs no eigen-decomposition and uses
// the filtered normals, so texture already smoothed away does not count as
// curvature.
#pragma once

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// #P curvatures C_i (units 1/length, ≥ 0). Points without other neighbors get 0.
/// If min_cos is given, it receives the smallest n_i·n_j over R_i as well
/// (Eq. 5 needs it, and the same pass over the neighbors finds it for free).
Eigen::VectorXd estimate_curvature(const Positions& P, const Normals& normals,
                                   const Neighborhoods& R, Eigen::VectorXd* min_cos = nullptr);

}  // namespace detexture
