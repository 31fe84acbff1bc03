#pragma once
// A triangle mesh of a swatch in its rest (material) configuration.
//
// Rest coordinates are planar, in metres, in the *lab* frame of the scene: the pull runs along
// +x. The material frame (weft axis) is at angle `material_angle` from the lab x axis:
// 0 for a weft test, π/4 for bias, π/2 for warp. Deformed positions have 2 (planar scene) or
// 3 coordinates per vertex and are stored flat: x[dim·v + k].

#include <Eigen/Core>
#include <vector>

namespace yarnfit::shell {

struct InteriorEdge {
  int v0 = 0, v1 = 0;  // the shared edge
  int a = 0;           // vertex opposite in the first triangle
  int b = 0;           // vertex opposite in the second triangle
  int t0 = 0, t1 = 0;  // the two triangles
};

struct ShellMesh {
  Eigen::MatrixX2d rest;        // #V × 2 rest positions [m]
  Eigen::MatrixX3i triangles;   // #T × 3, counter-clockwise in the rest plane
  std::vector<InteriorEdge> interior_edges;  // filled by build_interior_edges
  double material_angle = 0.0;  // weft axis angle from the lab x axis [rad]

  [[nodiscard]] int vertex_count() const { return static_cast<int>(rest.rows()); }
  [[nodiscard]] int triangle_count() const { return static_cast<int>(triangles.rows()); }
  [[nodiscard]] double rest_area(int t) const;
};

// Finds every edge shared by two triangles, with the opposite vertices (for bending).
void build_interior_edges(ShellMesh& mesh);

}  // namespace yarnfit::shell
