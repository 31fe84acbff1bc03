#include "yarn_fit/periodic/tile_placement.hpp"

#include <stdexcept>

namespace yarnfit::yarn {

void TilePlacement::update(const YarnTile& tile, const CoarseMap& map) {
  const int side = 2 * kCells + 1;
  m_vertex_count = tile.vertex_count();
  m_curved = map.deformation().curved();
  m_placements.resize(static_cast<std::size_t>(side * side * m_vertex_count));
  for (int ci = -kCells; ci <= kCells; ++ci) {
    for (int cj = -kCells; cj <= kCells; ++cj) {
      const std::size_t offset = static_cast<std::size_t>(((ci + kCells) * side + (cj + kCells)) * m_vertex_count);
      for (int v = 0; v < m_vertex_count; ++v) {
        Placement& p = m_placements[offset + static_cast<std::size_t>(v)];
        map.place(tile.reference_at(v, {ci, cj}), p.base, p.rotation);
      }
    }
  }
}

void TilePlacement::outside_cached_cells() {
  throw std::logic_error("yarn system: placement outside the cached cells");
}

}  // namespace yarnfit::yarn
