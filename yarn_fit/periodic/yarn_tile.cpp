#include "yarn_fit/periodic/yarn_tile.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace yarnfit::yarn {

Eigen::Vector3d YarnTile::reference_at(int v, const Cell& cell) const {
  Eigen::Vector3d x = reference[static_cast<std::size_t>(v)];
  x.head<2>() += lattice * Eigen::Vector2d(cell.i, cell.j);
  return x;
}

bool YarnTile::same_yarn_gap(int a, int b, const Cell& cell_b, double& gap) const {
  const TileEdgeElement& ea = edges[static_cast<std::size_t>(a)];
  const TileEdgeElement& eb = edges[static_cast<std::size_t>(b)];
  if (ea.yarn != eb.yarn) return false;
  const TileYarn& yarn = yarns[static_cast<std::size_t>(ea.yarn)];
  const double cycle = yarn.input_rest_length;
  // Edge b in cell_b lies on the copy of the yarn that holds edge a in (0, 0) when
  // cell_b + C_a − C_b = k · N for an integer k (C: cell of the edge's start along the
  // cycle, N: net offset); it is then k trips further along that yarn.
  const Cell delta = cell_b + ea.cycle_cell - eb.cycle_cell;
  const Cell n = yarn.net_offset;
  const double len_a = input_rest_lengths[static_cast<std::size_t>(a)];
  const double len_b = input_rest_lengths[static_cast<std::size_t>(b)];
  if (n.i == 0 && n.j == 0) {
    if (delta.i != 0 || delta.j != 0) return false;
    // Closed loop: the shorter way round.
    if (a == b) {
      gap = -len_a;
      return true;
    }
    double forward = eb.arc_start - ea.arc_start;
    if (forward < 0.0) forward += cycle;
    double backward = ea.arc_start - eb.arc_start;
    if (backward < 0.0) backward += cycle;
    gap = std::min(forward - len_a, backward - len_b);
    return true;
  }
  int k = 0;
  if (n.i != 0) {
    if (delta.i % n.i != 0) return false;
    k = delta.i / n.i;
    if (delta.j != k * n.j) return false;
  } else {
    if (delta.j % n.j != 0 || delta.i != 0) return false;
    k = delta.j / n.j;
  }
  const double arc_a = ea.arc_start;
  const double arc_b = eb.arc_start + k * cycle;
  gap = arc_b >= arc_a ? arc_b - (arc_a + len_a) : arc_a - (arc_b + len_b);
  return true;
}

namespace {

// The anchors of one yarn, along its edges in the tile as read: directors carried from edge to
// edge by parallel transport (the reference frame of discrete elastic rods), so the two frames
// a corner averages differ only by a small twist. Around the cycle the transported director
// comes back turned by the curve's holonomy Δ; spreading −Δ evenly over the edges closes it,
// every corner then seeing the same twist Δ/n between its edges.
void set_yarn_anchors(YarnTile& tile, const TileYarn& yarn) {
  const std::size_t n = yarn.edges.size();
  std::vector<Eigen::Vector3d> t(n), d(n);
  for (std::size_t k = 0; k < n; ++k) {
    const TileEdgeElement& edge = tile.edges[static_cast<std::size_t>(yarn.edges[k])];
    const Eigen::Vector3d v = tile.reference_at(edge.v1, edge.cell1) - tile.reference_at(edge.v0, Cell{0, 0});
    if (!(v.norm() > 0.0))
      throw Error(ErrorCategory::input, "yarn tile: edge " + std::to_string(yarn.edges[k]) + " has zero length");
    t[k] = v.normalized();
    d[k] = k == 0 ? anchor_along(v).director : carried_anchor({t[k - 1], d[k - 1]}, Eigen::Matrix3d::Identity(), v).director;
  }
  const Eigen::Vector3d back = carried_anchor({t[n - 1], d[n - 1]}, Eigen::Matrix3d::Identity(), t[0]).director;
  const double holonomy = std::atan2(d[0].cross(back).dot(t[0]), d[0].dot(back));
  for (std::size_t k = 0; k < n; ++k) {
    const double turn = -holonomy * static_cast<double>(k) / static_cast<double>(n);
    const Eigen::Vector3d director = std::cos(turn) * d[k] + std::sin(turn) * t[k].cross(d[k]);
    tile.edges[static_cast<std::size_t>(yarn.edges[k])].anchor = {t[k], director.normalized()};
  }
}

// Each edge's anchor (set_yarn_anchors), and each corner's rest curvature vector: the
// magnitude of the file's *RK (tile files and generators disagree on the frame its two
// components are in; its magnitude they share) along the direction of the corner's curvature
// as read. A straight corner as read keeps the magnitude along the first axis.
void set_anchors_and_rest_curvatures(YarnTile& tile, const std::vector<std::array<double, 2>>& rest) {
  for (const TileYarn& yarn : tile.yarns) set_yarn_anchors(tile, yarn);
  for (TileCorner& c : tile.corners) {
    const CornerFrames frames{tile.edges[static_cast<std::size_t>(c.edge_in)].anchor,
                              tile.edges[static_cast<std::size_t>(c.edge_out)].anchor};
    const Eigen::Vector2d shape = corner_curvature(tile.reference_at(c.v_prev, c.cell_prev),
                                                   tile.reference_at(c.vertex, Cell{0, 0}),
                                                   tile.reference_at(c.v_next, c.cell_next), frames);
    const auto& rk = rest[static_cast<std::size_t>(c.vertex)];
    const double magnitude = std::hypot(rk[0], rk[1]);
    const double norm = shape.norm();
    c.rest_curvature = norm > 1e-12 && std::isfinite(norm) ? Eigen::Vector2d(magnitude * shape / norm)
                                                           : Eigen::Vector2d(magnitude, 0.0);
  }
}

// Walks the edges' cycles, each one periodic yarn: its edges in order, their arc length and
// cell along the yarn, and where a yarn that crosses the period is pinned and slides.
void walk_yarns(YarnTile& out, const std::vector<int>& out_edge) {
  const int ne = static_cast<int>(out.edges.size());
  std::vector<bool> seen(static_cast<std::size_t>(ne), false);
  for (int start = 0; start < ne; ++start) {
    if (seen[static_cast<std::size_t>(start)]) continue;
    TileYarn yarn;
    const int yarn_index = static_cast<int>(out.yarns.size());
    Cell cell{0, 0};
    double arc = 0.0;
    int e = start;
    while (!seen[static_cast<std::size_t>(e)]) {
      seen[static_cast<std::size_t>(e)] = true;
      TileEdgeElement& el = out.edges[static_cast<std::size_t>(e)];
      el.yarn = yarn_index;
      el.arc_start = arc;
      el.cycle_cell = cell;
      yarn.edges.push_back(e);
      arc += el.rest_length;
      cell = cell + el.cell1;
      e = out_edge[static_cast<std::size_t>(el.v1)];
      if (e < 0) throw Error(ErrorCategory::input, "yarn tile: open yarn (vertex without outgoing edge)");
    }
    if (e != start) throw Error(ErrorCategory::input, "yarn tile: edges do not form closed cycles");
    yarn.net_offset = cell;
    yarn.input_rest_length = arc;
    if (cell.i != 0 || cell.j != 0) {
      yarn.pinned_vertices = {out.edges[static_cast<std::size_t>(start)].v0};
      const Eigen::Vector2d dir = out.lattice * Eigen::Vector2d(cell.i, cell.j);
      yarn.slide_direction = Eigen::Vector3d(dir.x(), dir.y(), 0.0).normalized();
    }
    out.yarns.push_back(std::move(yarn));
  }
}

// Each vertex's corner: the edges in and out and the neighbours they lead to.
void link_corners(YarnTile& out, const std::vector<int>& in_edge, const std::vector<int>& out_edge) {
  const int nv = static_cast<int>(in_edge.size());
  out.corners.resize(static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    TileCorner& c = out.corners[static_cast<std::size_t>(v)];
    const int ei = in_edge[static_cast<std::size_t>(v)];
    const int eo = out_edge[static_cast<std::size_t>(v)];
    const TileEdgeElement& in = out.edges[static_cast<std::size_t>(ei)];
    const TileEdgeElement& o = out.edges[static_cast<std::size_t>(eo)];
    c.vertex = v;
    c.edge_in = ei;
    c.edge_out = eo;
    c.v_prev = in.v0;
    c.cell_prev = -in.cell1;
    c.v_next = o.v1;
    c.cell_next = o.cell1;
  }
}

}  // namespace

YarnTile make_yarn_tile(const db::PeriodicTile& source) {
  db::PeriodicTile tile = source;
  db::fill_tile_defaults(tile);
  const int nv = tile.vertex_count();
  const int ne = tile.edge_count();
  if (nv == 0 || ne != nv)
    throw Error(ErrorCategory::input, "yarn tile: expected as many edges as vertices, got " +
                                std::to_string(ne) + " edges for " + std::to_string(nv) +
                                " vertices");
  YarnTile out;
  out.lattice << tile.period_x, 0.0, 0.0, tile.period_y;
  out.radius = tile.radius;

  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : tile.positions) centroid += Eigen::Vector3d(p[0], p[1], p[2]);
  centroid /= nv;
  out.reference.reserve(static_cast<std::size_t>(nv));
  for (const auto& p : tile.positions)
    out.reference.emplace_back(Eigen::Vector3d(p[0], p[1], p[2]) - centroid);

  std::vector<int> out_edge(static_cast<std::size_t>(nv), -1);
  std::vector<int> in_edge(static_cast<std::size_t>(nv), -1);
  for (int e = 0; e < ne; ++e) {
    const auto& te = tile.edges[static_cast<std::size_t>(e)];
    if (te.v0 < 0 || te.v0 >= nv || te.v1 < 0 || te.v1 >= nv)
      throw Error(ErrorCategory::input, "yarn tile: edge " + std::to_string(e) + " has a vertex out of range");
    if (out_edge[static_cast<std::size_t>(te.v0)] != -1 || in_edge[static_cast<std::size_t>(te.v1)] != -1)
      throw Error(ErrorCategory::input, "yarn tile: vertex with more than one outgoing or incoming edge");
    out_edge[static_cast<std::size_t>(te.v0)] = e;
    in_edge[static_cast<std::size_t>(te.v1)] = e;
    TileEdgeElement el;
    el.v0 = te.v0;
    el.v1 = te.v1;
    el.cell1 = {te.dx, te.dy};
    el.rest_length = tile.rest_lengths[static_cast<std::size_t>(e)];
    out.edges.push_back(el);
  }
  out.input_rest_lengths = tile.rest_lengths;

  walk_yarns(out, out_edge);
  link_corners(out, in_edge, out_edge);
  set_anchors_and_rest_curvatures(out, tile.rest_curvatures);
  return out;
}

YarnTile transformed_tile(const YarnTile& tile, const Eigen::Matrix2d& map) {
  YarnTile out = tile;
  out.lattice = map * tile.lattice;
  for (auto& x : out.reference) x.head<2>() = map * x.head<2>();
  for (auto& y : out.yarns) {
    const Eigen::Vector2d dir = map * y.slide_direction.head<2>();
    y.slide_direction = Eigen::Vector3d(dir.x(), dir.y(), 0.0).normalized();
  }
  return out;
}

YarnTile rotated_tile(const YarnTile& tile, double angle) {
  Eigen::Matrix2d rot;
  rot << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  YarnTile out = transformed_tile(tile, rot);
  Eigen::Matrix3d rot3 = Eigen::Matrix3d::Identity();
  rot3.topLeftCorner<2, 2>() = rot;
  for (auto& e : out.edges) e.anchor = {rot3 * e.anchor.tangent, rot3 * e.anchor.director};
  return out;
}

db::PeriodicTile repeat_tile(const db::PeriodicTile& tile, int nx, int ny) {
  if (nx < 1 || ny < 1) throw Error(ErrorCategory::input, "repeat_tile: counts must be >= 1");
  db::PeriodicTile t = tile;
  db::fill_tile_defaults(t);
  const int nv = t.vertex_count();
  db::PeriodicTile out;
  out.period_x = t.period_x * nx;
  out.period_y = t.period_y * ny;
  out.radius = t.radius;
  // Copy (a, b) of vertex v gets index v + nv·(a + nx·b).
  const auto floor_div = [](int value, int n) { return value >= 0 ? value / n : -((-value + n - 1) / n); };
  for (int b = 0; b < ny; ++b) {
    for (int a = 0; a < nx; ++a) {
      for (int v = 0; v < nv; ++v) {
        auto p = t.positions[static_cast<std::size_t>(v)];
        p[0] += a * t.period_x;
        p[1] += b * t.period_y;
        out.positions.push_back(p);
        out.twists.push_back(t.twists[static_cast<std::size_t>(v)]);
        out.rest_curvatures.push_back(t.rest_curvatures[static_cast<std::size_t>(v)]);
        out.rest_twists.push_back(t.rest_twists[static_cast<std::size_t>(v)]);
        out.reference_twists.push_back(t.reference_twists[static_cast<std::size_t>(v)]);
      }
    }
  }
  for (int b = 0; b < ny; ++b) {
    for (int a = 0; a < nx; ++a) {
      for (int e = 0; e < t.edge_count(); ++e) {
        const auto& te = t.edges[static_cast<std::size_t>(e)];
        const int ta = a + te.dx;
        const int tb = b + te.dy;
        const int ca = ((ta % nx) + nx) % nx;
        const int cb = ((tb % ny) + ny) % ny;
        db::TileEdge ne;
        ne.v0 = te.v0 + nv * (a + nx * b);
        ne.v1 = te.v1 + nv * (ca + nx * cb);
        ne.dx = floor_div(ta, nx);
        ne.dy = floor_div(tb, ny);
        out.edges.push_back(ne);
        out.rest_lengths.push_back(t.rest_lengths[static_cast<std::size_t>(e)]);
        out.reference_directors.push_back(t.reference_directors[static_cast<std::size_t>(e)]);
      }
    }
  }
  return out;
}

YarnTile repeat_yarn_tile(const db::PeriodicTile& tile, int nx, int ny) {
  const YarnTile base = make_yarn_tile(tile);
  YarnTile out = make_yarn_tile(repeat_tile(tile, nx, ny));
  // Vertex v of copy (a, b) has index v + nv·(a + nx·b) (repeat_tile's numbering).
  const int nv = base.vertex_count();
  std::vector<int> yarn_of(static_cast<std::size_t>(out.vertex_count()), -1);
  for (const auto& e : out.edges) yarn_of[static_cast<std::size_t>(e.v0)] = e.yarn;
  for (auto& y : out.yarns) y.pinned_vertices.clear();
  for (const auto& y : base.yarns) {
    for (const int p : y.pinned_vertices) {
      for (int copy = 0; copy < nx * ny; ++copy) {
        const int v = p + nv * copy;
        out.yarns[static_cast<std::size_t>(yarn_of[static_cast<std::size_t>(v)])].pinned_vertices.push_back(v);
      }
    }
  }
  return out;
}

}  // namespace yarnfit::yarn
