#include "detexture/tiling/run_tile.h"

#include <chrono>
#include <stdexcept>
#include <string>

namespace detexture {

TileResult run_tile(Positions P, Normals normals, const std::vector<std::uint8_t>& is_core,
                    const RemoveTextureParams& params, const PipelineObserver& observer) {
  if (is_core.size() != static_cast<std::size_t>(P.rows()))
    throw std::invalid_argument("run_tile: the core mask must have one entry per point");
  TileResult out;
  for (std::size_t i = 0; i < is_core.size(); ++i)
    if (is_core[i]) out.core.push_back(static_cast<std::uint32_t>(i));
  if (out.core.empty()) throw std::invalid_argument("run_tile: the tile has no core point");
  const auto start = std::chrono::steady_clock::now();
  RemoveTextureResult r = remove_texture(std::move(P), std::move(normals), params, observer);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto m = static_cast<Eigen::Index>(out.core.size());
  out.positions.resize(m, 3);
  out.normals.resize(m, 3);
  out.input_normals.resize(m, 3);
  out.is_texture.resize(out.core.size());
  out.texture_height.resize(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = out.core[static_cast<std::size_t>(k)];
    out.positions.row(k) = r.positions.row(i);
    out.normals.row(k) = r.normals.row(i);
    out.input_normals.row(k) = r.input_normals.row(i);
    out.is_texture[static_cast<std::size_t>(k)] = r.is_texture[static_cast<std::size_t>(i)];
    out.texture_height(k) = r.texture_height(i);
  }
  out.report = std::move(r.report);
  return out;
}

void rethrow_tile_failure(std::size_t tile, std::size_t points, bool wrap_other) {
  const std::string what =
      "tile " + std::to_string(tile) + " (" + std::to_string(points) + " points) failed: ";
  try {
    throw;
  } catch (const ResourceLimitError& e) {
    throw ResourceLimitError(what + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + e.what());
  } catch (const std::exception& e) {
    if (!wrap_other) throw;
    throw std::runtime_error(what + e.what());
  }
}

}  // namespace detexture
