#pragma once
// A periodic yarn tile prepared for simulation (thesis 3.3.2, A.2.1; SPEC §3 "Yarn").
//
// Built from a pyp tile (fabrics_db), with a general 2-D lattice so that a tile rotated in
// the plane is still a tile. Reference coordinates are relative to the tile centroid (x, y)
// and to the mid-plane (h = z − mean z), which is where the co-rotated map of a curved
// coarse deformation is anchored (A.1).
//
// Periodic elements. Every element is stored once, in one canonical placement: an edge from
// its v0 in cell (0, 0) to v1 in the edge's cell offset; a bending corner centred on its
// vertex in cell (0, 0); a contact pair as edge a in cell (0, 0) against edge b in cell c,
// with a < b, or a == b and c > (0, 0) lexicographically. Each periodic element is then
// counted exactly once: this is the fractional counting of A.2.1 with weight 1 on the
// canonical copy and 0 on the others, and since the periodic maps are equivariant under a
// shift by a period (affine: a translation; cylinder: a screw motion), every copy has the
// same energy. Pairs made of ghost copies only are never formed.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn {

struct Cell {
  int i = 0;
  int j = 0;
  friend bool operator==(const Cell&, const Cell&) = default;
  Cell operator+(const Cell& o) const { return {i + o.i, j + o.j}; }
  Cell operator-(const Cell& o) const { return {i - o.i, j - o.j}; }
  Cell operator-() const { return {-i, -j}; }
};

struct TileEdgeElement {
  int v0 = 0;
  int v1 = 0;
  Cell cell1;                // cell of v1 when v0 is in (0, 0)
  double rest_length = 0.0;  // current rest length L̄ [m] (the rest-shape heuristic edits it)
  int yarn = 0;
  double arc_start = 0.0;    // input rest length along the yarn before this edge [m]
  Cell cycle_cell;           // cell of v0 relative to the yarn's first vertex, walking the cycle
  EdgeAnchor anchor;         // where its material frame is carried from (the tile as read)
};

struct TileCorner {
  int vertex = 0;              // the middle vertex, in cell (0, 0)
  int v_prev = 0;              // previous vertex and its cell
  Cell cell_prev;
  int v_next = 0;              // next vertex and its cell
  Cell cell_next;
  int edge_in = 0;             // edge v_prev -> vertex
  int edge_out = 0;            // edge vertex -> v_next
  // κ̄: the rest curvature vector in the corner's material frames (rod_bending); the tile
  // file's *RK gives its magnitude and the tile's shape as read its direction.
  Eigen::Vector2d rest_curvature = Eigen::Vector2d::Zero();
};

struct TileYarn {
  std::vector<int> edges;       // in order along the yarn
  Cell net_offset;              // cells advanced after one trip (0, 0 for a closed loop)
  double input_rest_length = 0.0;
  // Vertices held on their boundary plane against parametric sliding (g · slide_direction
  // = 0): one per period of yarn, none for closed loops. The pin carries a reaction force
  // wherever the discrete rest lengths make sliding cost energy, so a tile repeated n times
  // must pin every copy of the original pins to describe the same material (repeat_yarn_tile).
  std::vector<int> pinned_vertices;
  Eigen::Vector3d slide_direction = Eigen::Vector3d::Zero();  // unit, along lattice·net_offset
};

struct YarnTile {
  Eigen::Matrix2d lattice = Eigen::Matrix2d::Zero();  // columns: period vectors [m]
  double radius = 0.0;                                // yarn radius from the file [m]
  std::vector<Eigen::Vector3d> reference;             // (X1, X2, h) per vertex [m]
  std::vector<TileEdgeElement> edges;
  std::vector<TileCorner> corners;  // one per vertex
  std::vector<TileYarn> yarns;
  std::vector<double> input_rest_lengths;  // *RL as read, for the ±20 % bound of 6.5.2

  [[nodiscard]] int vertex_count() const { return static_cast<int>(reference.size()); }
  [[nodiscard]] int edge_count() const { return static_cast<int>(edges.size()); }
  // Length of the shorter period vector [m].
  [[nodiscard]] double shorter_period() const { return std::min(lattice.col(0).norm(), lattice.col(1).norm()); }
  [[nodiscard]] double area() const {
    return std::abs(lattice(0, 0) * lattice(1, 1) - lattice(0, 1) * lattice(1, 0));
  }
  // Reference position of vertex v copied into `cell`.
  [[nodiscard]] Eigen::Vector3d reference_at(int v, const Cell& cell) const;

  // When edge a in cell (0, 0) and edge b in `cell_b` lie on the same infinite yarn, returns
  // true and sets `gap` to the input rest length of yarn strictly between them (≤ 0 when
  // they are the same edge or neighbours). Contact between such segments is skipped below
  // a gap threshold: nearby segments of one yarn are at distance ≈ gap along a straight yarn
  // and must not repel each other.
  bool same_yarn_gap(int a, int b, const Cell& cell_b, double& gap) const;
};

// Throws an input Error if the tile's edges do not form closed cycles.
YarnTile make_yarn_tile(const db::PeriodicTile& tile);

// The tile rotated in-plane by `angle` [rad] about the centroid: reference positions, lattice
// and the edges' frame anchors turn together (used for invariance checks and arbitrary
// material frames).
YarnTile rotated_tile(const YarnTile& tile, double angle);

// The tile's reference positions and lattice mapped by an in-plane linear map (rest lengths,
// curvatures and frame anchors unchanged, so the energy's change with the map is the coarse
// stress's work): used to adjust a tile's period at rest, and by rotated_tile.
YarnTile transformed_tile(const YarnTile& tile, const Eigen::Matrix2d& map);

// The pyp tile repeated nx × ny times (a larger but equivalent tile, for checks that the
// homogenised response does not depend on the tile chosen). Throws for nx, ny < 1.
db::PeriodicTile repeat_tile(const db::PeriodicTile& tile, int nx, int ny);

// make_yarn_tile(repeat_tile(tile, nx, ny)) with every copy of the original tile's pins
// pinned, so that the repeated tile has exactly the periodic states of the original among
// its own (same energy per area, same equilibria).
YarnTile repeat_yarn_tile(const db::PeriodicTile& tile, int nx, int ny);

}  // namespace yarnfit::yarn
