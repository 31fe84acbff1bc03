#pragma once
// Rectangular swatch meshes, refinement, vertex queries and material points.
//
// The swatch occupies [0, length] × [-width/2, width/2] in the lab frame of its scene (pull
// along +x, centre line y = 0; SPEC §3 "Shell"). Grids have (nx+1)×(ny+1) nodes with nx and ny
// even, so a node column sits exactly on mid-length x = length/2 (where compression is
// measured) and a node row on the centre line y = 0. Each grid cell is split into two
// counter-clockwise triangles whose diagonal alternates in a checkerboard, so the mesh has no
// preferred shear direction (a uniform diagonal makes a bias test respond differently at +45°
// and −45°).

#include <Eigen/Core>
#include <functional>
#include <utility>
#include <vector>

#include "shell_fit/core/shell_mesh.hpp"

namespace yarnfit::shell {

// Rectangle [0, length] × [-width/2, width/2] [m] with nx × ny cells; interior edges built.
// Throws an input Error unless length, width > 0 and finite, nx, ny ≥ 2 and even, and
// material_angle [rad] is finite.
ShellMesh make_rect_mesh(double length, double width, int nx, int ny, double material_angle);

// Splits every triangle into four at its edge midpoints (shared between neighbours), keeping
// the material angle; interior edges rebuilt. The original vertices keep their indices and
// come first; midpoints follow. Vertices on the boundary lines of a rectangle stay exactly
// on them, and mid-length columns stay exactly at mid-length.
ShellMesh refine(const ShellMesh& mesh);

// Grid resolution (nx, ny), both even and ≥ 2, whose cells are close to square with edges
// close to `target_edge` [m]: nx from length/target_edge, then ny from the resulting cell
// length. Throws an input Error for non-positive or non-finite inputs.
std::pair<int, int> default_resolution(double length, double width, double target_edge);

// Default distance [m] within which a vertex counts as lying on a query line: far above the
// rounding error of swatch coordinates (~1e-17 m) and far below any mesh spacing.
inline constexpr double vertex_query_tolerance = 1e-9;

// Vertices whose rest position satisfies `predicate`, sorted by rest y, then rest x.
std::vector<int> vertices_where(const ShellMesh& mesh,
                                const std::function<bool(const Eigen::Vector2d&)>& predicate);
// Vertices with |rest x − x| ≤ tol, sorted by rest y (e.g. a clamped edge at x = 0 or
// x = length, or the mid-length column).
std::vector<int> vertices_at_x(const ShellMesh& mesh, double x,
                               double tol = vertex_query_tolerance);
// Vertices with |rest y − y| ≤ tol, sorted by rest x.
std::vector<int> vertices_at_y(const ShellMesh& mesh, double y,
                               double tol = vertex_query_tolerance);

// A point fixed in the material (a gauge mark): a triangle and barycentric weights of its
// rest position in that triangle (weights sum to 1, all ≥ 0 up to rounding).
struct MaterialPoint {
  int triangle = 0;
  Eigen::Vector3d weights = Eigen::Vector3d::Zero();
};

// The material point at `rest_point` [m]. Points on an edge or vertex are given to the
// triangle where they are deepest inside. Throws an input Error if the point lies
// outside the mesh (beyond a tolerance of 1e-9 relative to the triangle).
MaterialPoint locate(const ShellMesh& mesh, const Eigen::Vector2d& rest_point);

// Deformed position (dim entries) of a material point: the barycentric interpolation of its
// triangle's vertices in x (flat, dim per vertex). Exact for affine deformations. Throws
// an input Error if x.size() ≠ dim·#V or the point's triangle is out of range.
Eigen::VectorXd deformed_position(const MaterialPoint& point, const ShellMesh& mesh,
                                  const Eigen::VectorXd& x, int dim);

// The rest positions flat with `dim` entries per vertex (z = 0 when dim = 3): the natural
// starting state of a scene.
Eigen::VectorXd rest_state(const ShellMesh& mesh, int dim);

}  // namespace yarnfit::shell
