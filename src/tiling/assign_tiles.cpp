#include <algorithm>
#include <numeric>

#include "detexture/tiling/remove_texture_mpi.h"

namespace detexture {

std::vector<int> assign_tiles(const std::vector<std::uint64_t>& core,
                              const std::vector<std::uint64_t>& points, int ranks) {
  std::vector<int> owner(core.size(), -1);
  std::vector<std::size_t> order(core.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&points](std::size_t a, std::size_t b) { return points[a] > points[b]; });
  std::vector<std::uint64_t> load(static_cast<std::size_t>(std::max(1, ranks)), 0);
  for (const std::size_t t : order) {
    if (core[t] == 0) continue;
    const auto least = std::min_element(load.begin(), load.end()) - load.begin();
    owner[t] = static_cast<int>(least);
    load[static_cast<std::size_t>(least)] += points[t];
  }
  return owner;
}

}  // namespace detexture
