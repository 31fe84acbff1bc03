// Rectangular swatch meshes: counts, orientation, area, refinement, interior edges, vertex
// queries and material points (shell_fit/mesh/rect_mesh.hpp).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "shell_fit/mesh/rect_mesh.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::shell {
namespace {

double total_rest_area(const ShellMesh& mesh) {
  double a = 0.0;
  for (int t = 0; t < mesh.triangle_count(); ++t) a += mesh.rest_area(t);
  return a;
}

double min_rest_area(const ShellMesh& mesh) {
  double a = std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh.triangle_count(); ++t) a = std::min(a, mesh.rest_area(t));
  return a;
}

// Number of distinct undirected edges.
int edge_count(const ShellMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      edges.insert(std::minmax(mesh.triangles(t, k), mesh.triangles(t, (k + 1) % 3)));
    }
  }
  return static_cast<int>(edges.size());
}

// Euler (disc: V − E + T = 1) and edge incidence (3T = 2·interior + boundary).
void expect_disc_topology(const ShellMesh& mesh, int boundary_edges) {
  const int v = mesh.vertex_count();
  const int t = mesh.triangle_count();
  const int e = edge_count(mesh);
  EXPECT_EQ(v - e + t, 1);
  const int interior = static_cast<int>(mesh.interior_edges.size());
  EXPECT_EQ(interior, e - boundary_edges);
  EXPECT_EQ(3 * t, 2 * interior + boundary_edges);
}

TEST(RectMesh, CountsOrientationAndArea) {
  const double length = 0.1, width = 0.06;
  const int nx = 20, ny = 12;
  const ShellMesh mesh = make_rect_mesh(length, width, nx, ny, 0.3);
  EXPECT_EQ(mesh.vertex_count(), (nx + 1) * (ny + 1));
  EXPECT_EQ(mesh.triangle_count(), 2 * nx * ny);
  EXPECT_DOUBLE_EQ(mesh.material_angle, 0.3);
  EXPECT_GT(min_rest_area(mesh), 0.0) << "every triangle must be counter-clockwise";
  EXPECT_NEAR(total_rest_area(mesh), length * width, 1e-15);
  EXPECT_DOUBLE_EQ(mesh.rest.col(0).minCoeff(), 0.0);
  EXPECT_DOUBLE_EQ(mesh.rest.col(0).maxCoeff(), length);
  EXPECT_DOUBLE_EQ(mesh.rest.col(1).minCoeff(), -width / 2);
  EXPECT_DOUBLE_EQ(mesh.rest.col(1).maxCoeff(), width / 2);
  expect_disc_topology(mesh, 2 * (nx + ny));
}

TEST(RectMesh, CheckerboardDiagonalsHaveNoDirectionalBias) {
  // Count each cell's diagonal by the sign of its slope: a checkerboard on an even grid has as
  // many rising as falling diagonals.
  const ShellMesh mesh = make_rect_mesh(1.0, 1.0, 4, 6, 0.0);
  int rising = 0, falling = 0;
  for (const InteriorEdge& e : mesh.interior_edges) {
    const Eigen::Vector2d d = (mesh.rest.row(e.v1) - mesh.rest.row(e.v0)).transpose();
    if (d.x() == 0.0 || d.y() == 0.0) continue;  // a grid line, not a diagonal
    (d.x() * d.y() > 0.0 ? rising : falling)++;
  }
  EXPECT_EQ(rising + falling, 4 * 6);
  EXPECT_EQ(rising, falling);
}

TEST(RectMesh, NodeLinesSitExactlyOnMidLengthAndCentreLine) {
  const double length = 0.0692, width = 0.0666;  // a swatch with awkward decimals
  const ShellMesh mesh = make_rect_mesh(length, width, 14, 10, 0.0);
  const auto mid = vertices_at_x(mesh, length / 2, 0.0);  // exact, no tolerance
  ASSERT_EQ(mid.size(), 11u);
  EXPECT_DOUBLE_EQ(mesh.rest(mid.front(), 1), -width / 2);
  EXPECT_DOUBLE_EQ(mesh.rest(mid.back(), 1), width / 2);
  EXPECT_EQ(vertices_at_y(mesh, 0.0, 0.0).size(), 15u);
  for (std::size_t k = 1; k < mid.size(); ++k) {
    EXPECT_LT(mesh.rest(mid[k - 1], 1), mesh.rest(mid[k], 1)) << "sorted by y";
  }
  const auto left = vertices_at_x(mesh, 0.0);
  const auto right = vertices_at_x(mesh, length);
  EXPECT_EQ(left.size(), 11u);
  EXPECT_EQ(right.size(), 11u);
  const auto corners = vertices_where(mesh, [&](const Eigen::Vector2d& p) {
    return std::abs(std::abs(p.y()) - width / 2) < 1e-12 &&
           (p.x() == 0.0 || p.x() == length);
  });
  EXPECT_EQ(corners.size(), 4u);
}

TEST(RectMesh, RejectsOddOrTooFewCellsAndBadSizes) {
  EXPECT_ERROR((void)make_rect_mesh(0.1, 0.06, 19, 12, 0.0), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)make_rect_mesh(0.1, 0.06, 20, 11, 0.0), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)make_rect_mesh(0.1, 0.06, 0, 12, 0.0), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)make_rect_mesh(-0.1, 0.06, 20, 12, 0.0), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)make_rect_mesh(0.1, std::nan(""), 20, 12, 0.0), yarnfit::ErrorCategory::input);
  try {
    (void)make_rect_mesh(0.1, 0.06, 7, 12, 0.0);
    FAIL() << "odd nx accepted";
  } catch (const yarnfit::Error& e) {
    EXPECT_NE(std::string(e.what()).find("nx"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("even"), std::string::npos) << e.what();
  }
}

TEST(RectMesh, RefinePreservesAreaAndQuadruplesTriangles) {
  const double length = 0.1, width = 0.06;
  const int nx = 6, ny = 4;
  const ShellMesh coarse = make_rect_mesh(length, width, nx, ny, std::numbers::pi / 4);
  const ShellMesh once = refine(coarse);
  const ShellMesh twice = refine(once);
  for (const auto* m : {&once, &twice}) {
    EXPECT_GT(min_rest_area(*m), 0.0);
    EXPECT_NEAR(total_rest_area(*m), length * width, 1e-15);
    EXPECT_DOUBLE_EQ(m->material_angle, std::numbers::pi / 4);
  }
  EXPECT_EQ(once.triangle_count(), 4 * coarse.triangle_count());
  EXPECT_EQ(twice.triangle_count(), 16 * coarse.triangle_count());
  // A refined grid is the (2nx)×(2ny) grid's node set.
  EXPECT_EQ(once.vertex_count(), (2 * nx + 1) * (2 * ny + 1));
  EXPECT_EQ(twice.vertex_count(), (4 * nx + 1) * (4 * ny + 1));
  expect_disc_topology(once, 2 * (2 * nx + 2 * ny));
  expect_disc_topology(twice, 2 * (4 * nx + 4 * ny));
  // Original vertices keep their indices; clamped edges and mid-length stay exact.
  EXPECT_TRUE(once.rest.topRows(coarse.vertex_count()).isApprox(coarse.rest, 0.0));
  EXPECT_EQ(vertices_at_x(twice, 0.0, 0.0).size(), static_cast<std::size_t>(4 * ny + 1));
  EXPECT_EQ(vertices_at_x(twice, length, 0.0).size(), static_cast<std::size_t>(4 * ny + 1));
  EXPECT_EQ(vertices_at_x(twice, length / 2, 0.0).size(), static_cast<std::size_t>(4 * ny + 1));
  // Every triangle of a refined grid is a half cell of the finer grid.
  const double half_cell = 0.5 * (length / (4 * nx)) * (width / (4 * ny));
  for (int t = 0; t < twice.triangle_count(); ++t) {
    ASSERT_NEAR(twice.rest_area(t), half_cell, 1e-12 * half_cell);
  }
}

TEST(RectMesh, MaterialPointsReproduceAnAffineMapExactly) {
  const ShellMesh mesh = make_rect_mesh(0.1, 0.06, 8, 6, 0.0);
  Eigen::Matrix2d f2;
  f2 << 1.4, 0.2, -0.1, 0.8;
  const Eigen::Vector2d shift2(0.01, -0.02);
  Eigen::Matrix<double, 3, 2> f3;
  f3 << 1.1, 0.3, 0.0, 0.9, 0.2, -0.4;
  const Eigen::Vector3d shift3(0.0, 0.5, 0.25);
  Eigen::VectorXd x2(2 * mesh.vertex_count()), x3(3 * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const Eigen::Vector2d p = mesh.rest.row(v).transpose();
    x2.segment<2>(2 * v) = f2 * p + shift2;
    x3.segment<3>(3 * v) = f3 * p + shift3;
  }
  const Eigen::VectorXd r2 = rest_state(mesh, 2);
  const Eigen::VectorXd r3 = rest_state(mesh, 3);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_EQ(r2(2 * v), mesh.rest(v, 0));
    EXPECT_EQ(r3(3 * v + 1), mesh.rest(v, 1));
    EXPECT_EQ(r3(3 * v + 2), 0.0);
  }

  // Gauge-like marks: interior points, a point on an edge, a vertex and a corner.
  const std::vector<Eigen::Vector2d> points = {
      {0.0203, 0.0117}, {0.05, 0.0}, {0.0125, -0.03}, {0.0, 0.0}, {0.1, 0.03}, {0.0777, -0.0211}};
  for (const auto& p : points) {
    const MaterialPoint mp = locate(mesh, p);
    EXPECT_GE(mp.weights.minCoeff(), 0.0);
    EXPECT_NEAR(mp.weights.sum(), 1.0, 1e-15);
    const Eigen::VectorXd y2 = deformed_position(mp, mesh, x2, 2);
    const Eigen::VectorXd y3 = deformed_position(mp, mesh, x3, 3);
    EXPECT_LT((y2 - (f2 * p + shift2)).norm(), 1e-15) << p.transpose();
    EXPECT_LT((y3 - (f3 * p + shift3)).norm(), 1e-15) << p.transpose();
    EXPECT_LT((deformed_position(mp, mesh, r2, 2) - p).norm(), 1e-17) << p.transpose();
  }
  EXPECT_ERROR((void)locate(mesh, Eigen::Vector2d(0.11, 0.0)), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)locate(mesh, Eigen::Vector2d(0.05, -0.0301)), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)deformed_position(locate(mesh, points[0]), mesh, x2, 3), yarnfit::ErrorCategory::input);
}

TEST(RectMesh, DefaultResolutionGivesEvenNearSquareCells) {
  EXPECT_EQ(default_resolution(0.1, 0.06, 0.005), std::make_pair(20, 12));
  for (const auto& [l, w, h] : {std::tuple{0.0692, 0.0666, 0.004}, std::tuple{0.1, 0.06, 0.0071},
                                std::tuple{0.02, 0.1, 0.003}, std::tuple{0.1, 0.001, 0.01}}) {
    const auto [nx, ny] = default_resolution(l, w, h);
    EXPECT_EQ(nx % 2, 0);
    EXPECT_EQ(ny % 2, 0);
    EXPECT_GE(nx, 2);
    EXPECT_GE(ny, 2);
    const double aspect = (l / nx) / (w / ny);
    if (w / (l / nx) >= 2.0) {  // enough room across for the cells to be near square
      EXPECT_GT(aspect, 0.6) << l << " " << w << " " << h;
      EXPECT_LT(aspect, 1.7) << l << " " << w << " " << h;
    }
    EXPECT_LT(std::abs(l / nx - h), 0.5 * h) << "cell length near the target";
  }
  EXPECT_ERROR((void)default_resolution(0.1, 0.06, 0.0), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::shell
