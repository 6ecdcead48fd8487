#include "detexture/tiling/tile_halo.h"

#include <limits>

namespace detexture {

double exact_tile_reach(const RemoveTextureParams& params) {
  if (params.update.mode == UpdateMode::Global) return std::numeric_limits<double>::infinity();
  const double r = params.radius.resolve(0.0, 0.0);
  // ρ_k ≤ r is assumed (R_i holding more than k points); see the header.
  // Fitted output normals read one more neighborhood, their blend another.
  const double output_normals =
      params.fit_normals ? (params.output_normals.blend_high_deg > 0.0 ? 2.0 : 1.0) : 0.0;
  return r + (4.0 + 3.0 * params.rolling.iterations + output_normals) * r;
}

}  // namespace detexture
