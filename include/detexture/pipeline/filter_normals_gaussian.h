// Texture removal (Sun et al. 2019, Sec. 4, Eq. 1): a Gaussian normal filter
// over the sub-neighborhood Ω_i, the non-texture points of R_i.
//
//   n¹_i = (1/W_i) Σ_{j∈Ω_i} w(p_i, p_j, σs) n_j,   w(x, y, σ) = exp(-|x-y|²/(2σ²))
//
// Membership of Ω_i comes as a weight ω_j (TextureDetection::omega): 0 or 1
// as in the paper, or between with the soft sub-neighborhood; the sum is
// then Σ_{j∈R_i} ω_j w(p_i, p_j, σs) n_j.
//
// Ω_i is empty when every point of R_i is texture (a point deep inside a
// texture feature wider than r). Then the filter falls back to the whole R_i
// — the plain Gaussian of Zheng et al. 2018 — and the point is counted: the
// structure-recovery iterations repair what the plain filter blurs.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

struct FilterNormalsGaussianParams {
  /// σs: spatial scale of the Gaussian weight, in the cloud's units; > 0.
  /// Texture smaller than σs is smoothed away.
  double sigma_s = 0.0;
  /// Use the sub-neighborhood Ω_i (the paper); false gives the plain Gaussian
  /// over R_i (the paper's Fig. 4 ablation, --no-subneighborhood).
  bool use_subneighborhood = true;
};

struct GaussianFilterResult {
  Normals normals;                         ///< #P by 3 unit normals n¹
  std::size_t empty_subneighborhoods = 0;  ///< points that fell back to R_i
  std::size_t zero_sum = 0;  ///< points whose weighted sum vanished: input normal kept
};

/// Eq. 1 for every point. `omega` (#P, ω_j in [0, 1], from detect_texture or
/// hard_omega) may be empty when use_subneighborhood is false; points whose
/// Ω_i weighs nothing fall back to R_i. Input normals must be oriented
/// consistently; zero input normals simply carry no weight.
GaussianFilterResult filter_normals_gaussian(const Positions& P, const Normals& normals,
                                             const Neighborhoods& R,
                                             const std::vector<float>& omega,
                                             const FilterNormalsGaussianParams& params);

void validate(const FilterNormalsGaussianParams& params);

}  // namespace detexture
