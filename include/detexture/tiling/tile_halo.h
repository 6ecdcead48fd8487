// How wide a tile's halo must be for its core points to get the whole-cloud
// result, derived from how far each stage of remove_texture reads.
//
// With r the neighborhood radius (R_i holds the points within r of p_i):
//   normals (when estimated): k nearest neighbors, reach ρ_k ≤ r wherever R_i
//     holds more than k points (the default k = 16; R_i holds ~190);
//   texture (Eq. 2): p_i's label counts the neighborhoods R_j, j ∈ R_i, in
//     which it fits the plane: 2r, read on normals that reach ρ_k further;
//   Gaussian filter (Eq. 1): sums over R_i of Ω-weighted normals: + r;
//   each rolling iteration (Eqs. 3-8): the guidance G_j of j ∈ R_i picks the
//     most reliable neighbor of j by a curvature read over R_j's neighbors:
//     + 3r per iteration (T iterations, 10 by default);
//   position update: the local modes (isotropic, eq9) read input positions
//     of R_i only: + r; the global solve couples all points (no finite reach);
//   output normals fitted to the output positions (the default): + r, and
//     their blend, which averages the neighbors' fits: + r more.
// The exact dependency cone is therefore ρ_k + (6 + 3T) r = 36r + ρ_k for
// the local updates with defaults (34r + ρ_k with filtered output normals),
// and unbounded for the global solve. The
// weights decay as exp(-d²/2σs²) (σs = r), so the influence of a point 3r
// away on a filtered normal is below exp(-4.5) ≈ 1% per step and compounds
// down along the cone: the default halo is therefore a measured 4r, not the
// cone (see README, "Large clouds and clusters", for the differences
// measured against the whole-cloud result at 2r, 4r and 8r).
//
// Some statistics of remove_texture are whole-cloud means or percentiles and
// are per tile in a tiled run: the texture height behind the move limit
// (99th percentile), σc of Eq. 8 (mean curvature sum), the rolling filter's
// early stop (mean normal change), the global solve's stopping residual, the
// normals' orientation seed (Hoppe MST per connected component) and the
// RANSAC generators' seeds (by the point's index in spatial order). A halo
// cannot make these equal; their effect is part of the measured difference.
#pragma once

#include <string>

#include "detexture/pipeline/remove_texture.h"

namespace detexture {

/// The exact dependency cone above in the cloud's units, for `params` with
/// absolute lengths (resolve_tile_params.h); infinity for the global update.
double exact_tile_reach(const RemoveTextureParams& params);

}  // namespace detexture
