#include "shell_fit/mesh/rect_mesh.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace yarnfit::shell {

namespace {

std::string describe(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

void require_positive(double v, const char* what) {
  if (!(std::isfinite(v) && v > 0.0)) {
    throw Error(ErrorCategory::input, std::string(what) + " must be positive and finite, got " +
                                describe(v));
  }
}

void require_even_cells(int n, const char* what) {
  if (n < 2 || n % 2 != 0) {
    throw Error(ErrorCategory::input, std::string(what) + " must be even and at least 2, got " +
                                std::to_string(n) +
                                " (an even count puts a node line on the swatch's mid-line)");
  }
}

// Nearest even integer ≥ 2 to v.
int even_at_least_two(double v) {
  const double halves = std::round(v / 2.0);
  return 2 * static_cast<int>(std::max(1.0, halves));
}

}  // namespace

ShellMesh make_rect_mesh(double length, double width, int nx, int ny, double material_angle) {
  require_positive(length, "rect mesh length");
  require_positive(width, "rect mesh width");
  require_even_cells(nx, "rect mesh nx (cells along the length)");
  require_even_cells(ny, "rect mesh ny (cells across the width)");
  if (!std::isfinite(material_angle)) {
    throw Error(ErrorCategory::input, "rect mesh material_angle must be finite, got " +
                                describe(material_angle));
  }

  ShellMesh mesh;
  mesh.material_angle = material_angle;
  const int columns = nx + 1;
  mesh.rest.resize(static_cast<Eigen::Index>(columns) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j) {
    // i/nx and (j − ny/2)/ny are exact at the ends and the middle (0, ±½, 1), so the clamped
    // edges, the free edges, mid-length and the centre line carry exact coordinates.
    const double y = width * (static_cast<double>(j - ny / 2) / ny);
    for (int i = 0; i <= nx; ++i) {
      const int v = j * columns + i;
      mesh.rest(v, 0) = length * (static_cast<double>(i) / nx);
      mesh.rest(v, 1) = y;
    }
  }

  mesh.triangles.resize(static_cast<Eigen::Index>(2) * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * columns + i;
      const int v10 = v00 + 1;
      const int v01 = v00 + columns;
      const int v11 = v01 + 1;
      if ((i + j) % 2 == 0) {  // diagonal v00–v11
        mesh.triangles.row(t++) << v00, v10, v11;
        mesh.triangles.row(t++) << v00, v11, v01;
      } else {  // diagonal v10–v01
        mesh.triangles.row(t++) << v00, v10, v01;
        mesh.triangles.row(t++) << v10, v11, v01;
      }
    }
  }
  build_interior_edges(mesh);
  return mesh;
}

ShellMesh refine(const ShellMesh& mesh) {
  const int nv = mesh.vertex_count();
  const int nt = mesh.triangle_count();
  // Each edge gets one midpoint, looked up by its sorted vertex pair.
  std::unordered_map<std::int64_t, int> midpoint_of;
  midpoint_of.reserve(static_cast<std::size_t>(3 * nt));
  std::vector<Eigen::Vector2d> midpoints;
  midpoints.reserve(static_cast<std::size_t>(3 * nt) / 2 + 1);
  const auto midpoint = [&](int a, int b) {
    const int lo = std::min(a, b);
    const int hi = std::max(a, b);
    const std::int64_t key = static_cast<std::int64_t>(lo) * nv + hi;
    const auto [it, inserted] = midpoint_of.try_emplace(key, nv + static_cast<int>(midpoints.size()));
    if (inserted) {
      // 0.5·(a + b) keeps a midpoint exactly on any line x = c or y = c its ends lie on.
      midpoints.emplace_back(0.5 * (mesh.rest.row(lo).transpose() + mesh.rest.row(hi).transpose()));
    }
    return it->second;
  };

  ShellMesh fine;
  fine.material_angle = mesh.material_angle;
  fine.triangles.resize(static_cast<Eigen::Index>(4) * nt, 3);
  for (int t = 0; t < nt; ++t) {
    const int a = mesh.triangles(t, 0);
    const int b = mesh.triangles(t, 1);
    const int c = mesh.triangles(t, 2);
    const int ab = midpoint(a, b);
    const int bc = midpoint(b, c);
    const int ca = midpoint(c, a);
    // Same orientation as the parent: three corner triangles and the middle one.
    fine.triangles.row(4 * t + 0) << a, ab, ca;
    fine.triangles.row(4 * t + 1) << ab, b, bc;
    fine.triangles.row(4 * t + 2) << ca, bc, c;
    fine.triangles.row(4 * t + 3) << ab, bc, ca;
  }
  fine.rest.resize(nv + static_cast<Eigen::Index>(midpoints.size()), 2);
  fine.rest.topRows(nv) = mesh.rest;
  for (std::size_t k = 0; k < midpoints.size(); ++k) {
    fine.rest.row(nv + static_cast<Eigen::Index>(k)) = midpoints[k].transpose();
  }
  build_interior_edges(fine);
  return fine;
}

std::pair<int, int> default_resolution(double length, double width, double target_edge) {
  require_positive(length, "default_resolution length");
  require_positive(width, "default_resolution width");
  require_positive(target_edge, "default_resolution target_edge");
  const int nx = even_at_least_two(length / target_edge);
  const double cell = length / nx;  // the actual cell length, so cells come out near square
  const int ny = even_at_least_two(width / cell);
  return {nx, ny};
}

std::vector<int> vertices_where(const ShellMesh& mesh,
                                const std::function<bool(const Eigen::Vector2d&)>& predicate) {
  std::vector<int> found;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (predicate(mesh.rest.row(v).transpose())) found.push_back(v);
  }
  std::sort(found.begin(), found.end(), [&](int a, int b) {
    if (mesh.rest(a, 1) != mesh.rest(b, 1)) return mesh.rest(a, 1) < mesh.rest(b, 1);
    return mesh.rest(a, 0) < mesh.rest(b, 0);
  });
  return found;
}

std::vector<int> vertices_at_x(const ShellMesh& mesh, double x, double tol) {
  return vertices_where(mesh, [&](const Eigen::Vector2d& p) { return std::abs(p.x() - x) <= tol; });
}

std::vector<int> vertices_at_y(const ShellMesh& mesh, double y, double tol) {
  std::vector<int> found;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (std::abs(mesh.rest(v, 1) - y) <= tol) found.push_back(v);
  }
  std::sort(found.begin(), found.end(),
            [&](int a, int b) { return mesh.rest(a, 0) < mesh.rest(b, 0); });
  return found;
}

MaterialPoint locate(const ShellMesh& mesh, const Eigen::Vector2d& rest_point) {
  if (!rest_point.allFinite()) {
    throw Error(ErrorCategory::input, "locate: rest point is not finite");
  }
  // The smallest barycentric weight measures how deep inside a triangle the point is; the
  // triangle that maximises it is the containing one (ties on shared edges go to the first).
  MaterialPoint best;
  double best_depth = -std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh.triangle_count(); ++t) {
    const Eigen::Vector2d p0 = mesh.rest.row(mesh.triangles(t, 0)).transpose();
    const Eigen::Vector2d e1 = mesh.rest.row(mesh.triangles(t, 1)).transpose() - p0;
    const Eigen::Vector2d e2 = mesh.rest.row(mesh.triangles(t, 2)).transpose() - p0;
    const double det = e1.x() * e2.y() - e1.y() * e2.x();
    if (det == 0.0) continue;  // degenerate: contains nothing
    const Eigen::Vector2d d = rest_point - p0;
    const double w1 = (d.x() * e2.y() - d.y() * e2.x()) / det;
    const double w2 = (e1.x() * d.y() - e1.y() * d.x()) / det;
    const double w0 = 1.0 - w1 - w2;
    const double depth = std::min({w0, w1, w2});
    if (depth > best_depth) {
      best_depth = depth;
      best.triangle = t;
      best.weights = Eigen::Vector3d(w0, w1, w2);
    }
  }
  constexpr double outside_tolerance = 1e-9;  // relative to the triangle: rounding only
  if (!(best_depth >= -outside_tolerance)) {
    std::ostringstream msg;
    msg << "locate: rest point (" << rest_point.x() << ", " << rest_point.y()
        << ") m lies outside the mesh";
    throw Error(ErrorCategory::input, msg.str());
  }
  // Rounding can leave a weight at −1e-16 for a point on an edge; clamp and renormalise so
  // the interpolation stays a convex combination.
  best.weights = best.weights.cwiseMax(0.0);
  best.weights /= best.weights.sum();
  return best;
}

Eigen::VectorXd deformed_position(const MaterialPoint& point, const ShellMesh& mesh,
                                  const Eigen::VectorXd& x, int dim) {
  if (dim < 1 || x.size() != static_cast<Eigen::Index>(dim) * mesh.vertex_count()) {
    throw Error(ErrorCategory::input, "deformed_position: x has " + std::to_string(x.size()) +
                                " entries, expected dim·#V = " + std::to_string(dim) + "·" +
                                std::to_string(mesh.vertex_count()));
  }
  if (point.triangle < 0 || point.triangle >= mesh.triangle_count()) {
    throw Error(ErrorCategory::input, "deformed_position: triangle " + std::to_string(point.triangle) +
                                " is out of range (mesh has " +
                                std::to_string(mesh.triangle_count()) + ")");
  }
  Eigen::VectorXd p = Eigen::VectorXd::Zero(dim);
  for (int k = 0; k < 3; ++k) {
    const int v = mesh.triangles(point.triangle, k);
    p += point.weights(k) * x.segment(static_cast<Eigen::Index>(dim) * v, dim);
  }
  return p;
}

Eigen::VectorXd rest_state(const ShellMesh& mesh, int dim) {
  if (dim != 2 && dim != 3) {
    throw Error(ErrorCategory::input, "rest_state: dim must be 2 or 3, got " + std::to_string(dim));
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dim) * mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    x(dim * v) = mesh.rest(v, 0);
    x(dim * v + 1) = mesh.rest(v, 1);
  }
  return x;
}

}  // namespace yarnfit::shell
