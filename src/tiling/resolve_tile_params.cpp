#include "detexture/tiling/resolve_tile_params.h"

namespace detexture {

RemoveTextureParams resolve_tile_params(const RemoveTextureParams& params,
                                        const TileLengths& lengths) {
  validate(params);
  const double d = lengths.diagonal, r = lengths.radius.radius;
  RemoveTextureParams p = params;
  p.radius = {r, Length::Unit::Absolute};
  for (Length* len :
       {&p.lambda, &p.sigma_s, &p.sigma_p, &p.solve_radius, &p.fit_sigma, &p.min_surface_radius})
    *len = {len->resolve(d, r), Length::Unit::Absolute};
  p.allow_large_radius = true;
  validate(p);
  return p;
}

}  // namespace detexture
