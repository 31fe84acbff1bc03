#pragma once
// Where the vertices of a periodic tile and their ghost copies sit under a coarse map
// (coarse_map.hpp): x = Φ(X, h) + R(X) g for vertex v copied into cell c, with Φ and R cached
// per (v, c) for the cells within kCells of the tile. Every yarn energy term reads its
// element positions here, so a term never needs to know whether the map is affine or
// co-rotated.

#include <Eigen/Core>
#include <vector>

#include "yarn_fit/periodic/coarse_map.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

class TilePlacement {
 public:
  static constexpr int kCells = 3;  // placements cached for cells in [-3, 3]²

  struct Placement {
    Eigen::Vector3d base;      // Φ(X, h) of the copy [m]
    Eigen::Matrix3d rotation;  // R(X): the co-rotated frame of its fluctuation
  };

  // Recomputes every cached placement of `tile` under `map`.
  void update(const YarnTile& tile, const CoarseMap& map);

  // Throws std::logic_error for a cell outside the cached range (a tile or contact list that
  // reaches further than periodic elements can). Inline: every element evaluation asks for
  // the placements of its vertices.
  [[nodiscard]] const Placement& at(int v, const Cell& cell) const {
    if (cell.i > kCells || cell.i < -kCells || cell.j > kCells || cell.j < -kCells) outside_cached_cells();
    constexpr int side = 2 * kCells + 1;
    return m_placements[static_cast<std::size_t>(((cell.i + kCells) * side + (cell.j + kCells)) * m_vertex_count + v)];
  }
  // Deformed position of vertex v copied into `cell`, for fluctuations g (3 per vertex).
  [[nodiscard]] Eigen::Vector3d position(const Eigen::VectorXd& g, int v, const Cell& cell) const {
    const Placement& p = at(v, cell);
    const Eigen::Vector3d gv = g.segment<3>(3 * v);
    return m_curved ? Eigen::Vector3d(p.base + p.rotation * gv) : Eigen::Vector3d(p.base + gv);
  }
  // κ ≠ 0: R varies over the tile and derivatives must be turned back into g-space.
  [[nodiscard]] bool curved() const { return m_curved; }

 private:
  [[noreturn]] static void outside_cached_cells();
  int m_vertex_count = 0;
  bool m_curved = false;
  std::vector<Placement> m_placements;
};

}  // namespace yarnfit::yarn
