// Guidance normals for the rolling filter (Sun et al. 2019, Sec. 5, Eqs. 4-8).
//
// Patch shift (Eqs. 4-6): every point gets a reliability
//   R(p_i) = max_{j∈R_i} D(p_ij) · C(p_i)        (Eq. 4)
// where D measures the normal difference between p_i and p_j (Eq. 5) and C is
// the mean curvature (estimate_curvature.h). Each point then takes, as its
// guidance, the current normal of the neighbor with the smallest R — the most
// reliable, flattest patch around it (Eq. 6).
//
// Blend (Eqs. 7-8): where the surroundings are curved the patch shift is
// unreliable (thin parts, tiptoes), so the guidance leans back to the current
// normal:
//   G'_i = α_i G_i + (1-α_i) n_i,   α_i = exp(-Σ_{j∈R_i} C(p_j) / σc)
// with σc the mean over all points of Σ_{j∈R_i} C(p_j), as the paper says.
//
// Which is the default. Measured on both quality suites (bench/RESULTS.md,
// `patch-shift` row), the plain guidance of Zheng et al. — G = the current
// normals — is as good or better in every one of the 18 cases: within 0.3%
// on bench/quality, and 0-10% lower normal error on the real shapes (knot
// 3.98° → 3.60°, person 6.50° → 6.09°, spider 10.42° → 9.89°), with the
// residual texture within +0.2% to −5%. The creases the patch shift is
// there for are already kept by the sheet split (drop_opposite_neighbors.h)
// and the further RANSAC planes of Eq. 2, and on curved and thin parts the
// flattest neighbor's normal is the wrong one. So Plain is the default and
// the paper's patch shift stays available (GuidanceMode::PatchShift,
// `--guidance patch-shift`).
//
// Choices where the paper is silent: D is the angle between the normals (the
// paper's words, "angle differences"; 1 - cos is available and orders points
// the same within a neighborhood); ties in R go to the nearer neighbor (the
// neighborhood order); the blended guidance is renormalized.
#pragma once

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

enum class GuidanceMode {
  PatchShift,  ///< the paper: Eqs. 4-8
  Plain,  ///< classic rolling guidance (Zheng et al. 2018): G = current normals (the default, see
          ///< above)
};

enum class NormalDifference {
  Angle,        ///< D = angle between n_i and n_j, in radians
  OneMinusCos,  ///< D = 1 - n_i·n_j
};

struct GuidanceNormalsParams {
  GuidanceMode mode = GuidanceMode::Plain;  ///< see above
  NormalDifference difference = NormalDifference::Angle;
  /// Apply the α blend of Eqs. 7-8 (PatchShift only).
  bool blend = true;
};

/// The guidance G^k (Eqs. 4-8) from the current normals (#P by 3, unit).
Normals guidance_normals(const Positions& P, const Normals& current, const Neighborhoods& R,
                         const GuidanceNormalsParams& params);

}  // namespace detexture
