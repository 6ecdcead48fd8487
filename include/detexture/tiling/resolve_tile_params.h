// The parameters every tile of a tiled run shares: each length resolved once,
// against the whole cloud, so that a tile does not resolve "0.02d" against its
// own (smaller) diagonal or estimate its own texture scale.
#pragma once

#include "detexture/pipeline/remove_texture.h"

namespace detexture {

/// Lengths of a tiled run, resolved against the whole cloud.
struct TileLengths {
  double diagonal = 0.0;  ///< of the whole cloud's bounding box
  RadiusChoice radius;    ///< r and why
  bool scale_estimated = false;
  TextureScaleEstimate scale;  ///< when r is a multiple of the texture radius
};

/// `params` with r, λ, σs, σp, the solve radius, the normal fit's σ and the
/// least surface radius given in the cloud's units (resolved from `lengths`), and the
/// neighborhood-share guard off (a tile on the rim of the cloud holds few
/// points, and the guard was checked on the whole cloud by the caller).
/// Throws std::invalid_argument (validate) for bad parameters.
RemoveTextureParams resolve_tile_params(const RemoveTextureParams& params,
                                        const TileLengths& lengths);

}  // namespace detexture
