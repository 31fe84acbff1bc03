#include "yarn_fit/periodic/yarn_system.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "fabrics_db/tile/segment_distance.hpp"

namespace yarnfit::yarn {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-kInf);
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void add(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  [[nodiscard]] bool overlaps(const Box& o, double margin) const {
    return (lo.array() - margin <= o.hi.array()).all() && (o.lo.array() <= hi.array() + margin).all();
  }
};

db::Point3 to_point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::vector<std::string> Effects::names(const CoarseDeformation& chi) const {
  std::vector<std::string> out;
  if (stretch) out.emplace_back("stretch");
  if (bending) out.emplace_back("bending");
  if (contact) out.emplace_back("contact");
  if (chi.curved()) out.emplace_back("co-rotation");
  return out;
}

YarnSystem::YarnSystem(YarnTile tile, const YarnParams& params, const Effects& effects)
    : m_tile(std::move(tile)), m_effects(effects), m_map(CoarseDeformation{}) {
  set_params(params);
  set_deformation(CoarseDeformation{});
  build_constraints();
}

void YarnSystem::set_params(const YarnParams& params) {
  if (const auto reason = params.invalid_reason())
    throw std::invalid_argument("yarn parameters: " + *reason);
  m_params = params;
  m_stretch = {params.ks1, params.ks2, params.eps_s};
  m_bending = {params.kb};
  m_contact = {params.kc1, params.r1, params.kc2, params.r2};
  m_skin = 1.5 * std::max(params.r1, params.r2);
  m_contacts_valid = false;
}

void YarnSystem::set_tile(YarnTile tile) {
  if (tile.vertex_count() != m_tile.vertex_count() || tile.edge_count() != m_tile.edge_count())
    throw std::invalid_argument("yarn system: set_tile needs the same vertices and edges");
  m_tile = std::move(tile);
  prepare_placements(m_map, m_placements);
  build_constraints();
  m_contacts_valid = false;
}

void YarnSystem::set_deformation(const CoarseDeformation& chi) {
  m_map = CoarseMap(chi);
  prepare_placements(m_map, m_placements);
  m_contacts_valid = false;
}

void YarnSystem::prepare_placements(const CoarseMap& map, std::vector<Placement>& out) const {
  const int side = 2 * kCells + 1;
  const int nv = m_tile.vertex_count();
  out.resize(static_cast<std::size_t>(side * side * nv));
  for (int ci = -kCells; ci <= kCells; ++ci) {
    for (int cj = -kCells; cj <= kCells; ++cj) {
      const std::size_t offset = static_cast<std::size_t>(((ci + kCells) * side + (cj + kCells)) * nv);
      for (int v = 0; v < nv; ++v) {
        Placement& p = out[offset + static_cast<std::size_t>(v)];
        map.place(m_tile.reference_at(v, {ci, cj}), p.base, p.rotation);
      }
    }
  }
}

const YarnSystem::Placement& YarnSystem::placement(int v, const Cell& cell) const {
  if (std::abs(cell.i) > kCells || std::abs(cell.j) > kCells)
    throw std::logic_error("yarn system: placement outside the cached cells");
  const int side = 2 * kCells + 1;
  return m_placements[static_cast<std::size_t>(((cell.i + kCells) * side + (cell.j + kCells)) *
                                                   m_tile.vertex_count() +
                                               v)];
}

Eigen::Vector3d YarnSystem::position(const Eigen::VectorXd& g, int v, const Cell& cell) const {
  const Placement& p = placement(v, cell);
  const Eigen::Vector3d gv = g.segment<3>(3 * v);
  if (!deformation().curved()) return p.base + gv;
  return p.base + p.rotation * gv;
}

void YarnSystem::build_constraints() {
  const int n = m_tile.vertex_count();
  int pinned = 0;
  for (const auto& y : m_tile.yarns) pinned += static_cast<int>(y.pinned_vertices.size());
  m_constraints = Eigen::MatrixXd::Zero(3 + pinned, 3 * n);
  for (int v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) m_constraints(k, 3 * v + k) = 1.0;
  int row = 3;
  for (const auto& y : m_tile.yarns) {
    for (const int p : y.pinned_vertices) {
      m_constraints.block<1, 3>(row, 3 * p) = y.slide_direction.transpose();
      ++row;
    }
  }
}

// ---------------------------------------------------------------------------------------
// Element loop. `Sink` receives each element's vertices (vertex index + placement) and its
// local energy, gradient and Hessian.

namespace {

template <int NV>
struct ElementVerts {
  std::array<int, NV> vertex;
  std::array<Cell, NV> cell;
};

}  // namespace

template <class Visitor>
void YarnSystem::for_each_element(const Eigen::VectorXd& g, Visitor&& visit) const {
  const bool curved = deformation().curved();
  const auto pos = [&](int v, const Cell& c) -> Eigen::Vector3d {
    const Placement& p = placement(v, c);
    const Eigen::Vector3d gv = g.segment<3>(3 * v);
    return curved ? Eigen::Vector3d(p.base + p.rotation * gv) : Eigen::Vector3d(p.base + gv);
  };
  if (m_effects.stretch) {
    for (const auto& e : m_tile.edges) {
      ElementVerts<2> ev{{e.v0, e.v1}, {Cell{0, 0}, e.cell1}};
      const Eigen::Vector3d x0 = pos(e.v0, {0, 0});
      const Eigen::Vector3d x1 = pos(e.v1, e.cell1);
      visit(0, ev, [&](Vec<6>* grad, Mat<6>* hess, bool project) {
        return stretch_element(x0, x1, e.rest_length, m_stretch, grad, hess, project);
      });
    }
  }
  if (m_effects.bending) {
    for (const auto& c : m_tile.corners) {
      ElementVerts<3> ev{{c.v_prev, c.vertex, c.v_next}, {c.cell_prev, Cell{0, 0}, c.cell_next}};
      const Eigen::Vector3d x0 = pos(c.v_prev, c.cell_prev);
      const Eigen::Vector3d x1 = pos(c.vertex, {0, 0});
      const Eigen::Vector3d x2 = pos(c.v_next, c.cell_next);
      const double la = m_tile.edges[static_cast<std::size_t>(c.edge_in)].rest_length;
      const double lb = m_tile.edges[static_cast<std::size_t>(c.edge_out)].rest_length;
      visit(1, ev, [&](Vec<9>* grad, Mat<9>* hess, bool project) {
        return bending_element(x0, x1, x2, la, lb, c.rest_curvature, m_bending, grad, hess, project);
      });
    }
  }
  if (m_effects.contact) {
    for (const auto& cc : m_contacts) {
      const auto& ea = m_tile.edges[static_cast<std::size_t>(cc.a)];
      const auto& eb = m_tile.edges[static_cast<std::size_t>(cc.b)];
      const Cell b1 = cc.cell + eb.cell1;
      ElementVerts<4> ev{{ea.v0, ea.v1, eb.v0, eb.v1}, {Cell{0, 0}, ea.cell1, cc.cell, b1}};
      const Eigen::Vector3d a0 = pos(ea.v0, {0, 0});
      const Eigen::Vector3d a1 = pos(ea.v1, ea.cell1);
      const Eigen::Vector3d p0 = pos(eb.v0, cc.cell);
      const Eigen::Vector3d p1 = pos(eb.v1, b1);
      visit(2, ev, [&](Vec<12>* grad, Mat<12>* hess, bool project) {
        return contact_element(a0, a1, p0, p1, ea.rest_length, eb.rest_length, m_contact, grad,
                               hess, project);
      });
    }
  }
}

double YarnSystem::energy(const Eigen::VectorXd& g) const {
  double total = 0.0;
  for_each_element(g, [&](int, const auto& ev, auto&& element) {
    constexpr int nv = static_cast<int>(std::tuple_size_v<decltype(ev.vertex)>);
    const double e = element(static_cast<Vec<3 * nv>*>(nullptr), static_cast<Mat<3 * nv>*>(nullptr), false);
    total += e;
  });
  return std::isfinite(total) ? total : kInf;
}

YarnSystem::Breakdown YarnSystem::energy_breakdown(const Eigen::VectorXd& g) const {
  Breakdown b;
  for_each_element(g, [&](int kind, const auto& ev, auto&& element) {
    constexpr int nv = static_cast<int>(std::tuple_size_v<decltype(ev.vertex)>);
    const double e = element(static_cast<Vec<3 * nv>*>(nullptr), static_cast<Mat<3 * nv>*>(nullptr), false);
    (kind == 0 ? b.stretch : kind == 1 ? b.bending : b.contact) += e;
  });
  return b;
}

double YarnSystem::energy_gradient(const Eigen::VectorXd& g, Eigen::VectorXd& gradient) const {
  gradient = Eigen::VectorXd::Zero(dof_count());
  const bool curved = deformation().curved();
  double total = 0.0;
  for_each_element(g, [&](int, const auto& ev, auto&& element) {
    constexpr int nv = static_cast<int>(std::tuple_size_v<decltype(ev.vertex)>);
    Vec<3 * nv> local;
    const double e = element(&local, static_cast<Mat<3 * nv>*>(nullptr), false);
    total += e;
    if (!std::isfinite(e) || e == 0.0) return;
    for (int i = 0; i < nv; ++i) {
      const Eigen::Vector3d gi = local.template segment<3>(3 * i);
      const int v = ev.vertex[static_cast<std::size_t>(i)];
      if (curved)
        gradient.segment<3>(3 * v) += placement(v, ev.cell[static_cast<std::size_t>(i)]).rotation.transpose() * gi;
      else
        gradient.segment<3>(3 * v) += gi;
    }
  });
  return std::isfinite(total) ? total : kInf;
}

void YarnSystem::hessian(const Eigen::VectorXd& g, Triplets& out, bool project_psd, bool lower_only) const {
  const bool curved = deformation().curved();
  for_each_element(g, [&](int, const auto& ev, auto&& element) {
    constexpr int nv = static_cast<int>(std::tuple_size_v<decltype(ev.vertex)>);
    Mat<3 * nv> local;
    local.setZero();
    const double e = element(static_cast<Vec<3 * nv>*>(nullptr), &local, project_psd);
    // Contact pairs beyond the cutoff have a zero block: leave them out of the pattern.
    if (!std::isfinite(e) || (nv == 4 && e == 0.0)) return;
    if (curved) {
      Eigen::Matrix<double, 3 * nv, 3 * nv> r = Eigen::Matrix<double, 3 * nv, 3 * nv>::Zero();
      for (int i = 0; i < nv; ++i)
        r.template block<3, 3>(3 * i, 3 * i) =
            placement(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]).rotation;
      local = (r.transpose() * local * r).eval();
    }
    for (int i = 0; i < nv; ++i) {
      const int vi = ev.vertex[static_cast<std::size_t>(i)];
      for (int j = 0; j < nv; ++j) {
        const int vj = ev.vertex[static_cast<std::size_t>(j)];
        if (lower_only && vi < vj) continue;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            if (!lower_only || 3 * vi + a >= 3 * vj + b)
              out.emplace_back(3 * vi + a, 3 * vj + b, local(3 * i + a, 3 * j + b));
      }
    }
  });
}

Eigen::Matrix2d YarnSystem::coarse_stress(const Eigen::VectorXd& g) const {
  Eigen::Matrix2d p = Eigen::Matrix2d::Zero();
  for_each_element(g, [&](int, const auto& ev, auto&& element) {
    constexpr int nv = static_cast<int>(std::tuple_size_v<decltype(ev.vertex)>);
    Vec<3 * nv> local;
    const double e = element(&local, static_cast<Mat<3 * nv>*>(nullptr), false);
    if (!std::isfinite(e) || e == 0.0) return;
    for (int i = 0; i < nv; ++i) {
      const Eigen::Vector3d ref =
          m_tile.reference_at(ev.vertex[static_cast<std::size_t>(i)], ev.cell[static_cast<std::size_t>(i)]);
      p += local.template segment<2>(3 * i) * ref.head<2>().transpose();
    }
  });
  return p / area();
}

double YarnSystem::energy_with(const Eigen::VectorXd& g, const CoarseDeformation& chi) const {
  YarnSystem copy = *this;
  const bool keep_contacts = copy.m_contacts_valid;
  const auto contacts = copy.m_contacts;
  copy.set_deformation(chi);
  // The candidate list was built for the current map; a central-difference step moves
  // vertices by far less than the skin, so it stays valid.
  if (keep_contacts) {
    copy.m_contacts = contacts;
    copy.m_contacts_valid = true;
  }
  return copy.energy(g);
}

double YarnSystem::d_energy_density(const Eigen::VectorXd& g, Coordinate q) const {
  const CoarseDeformation chi = deformation();
  if (!chi.curved() && q != Coordinate::curvature) {
    const Eigen::Matrix2d p = coarse_stress(g);
    const Eigen::Vector2d u = chi.u();
    const Eigen::Vector2d v = chi.v();
    return q == Coordinate::stretch ? u.dot(p * u) : -v.dot(p * v);
  }
  // Central differences of the map at fixed g (the co-rotated map's derivative). The step
  // is small against the coordinate's scale: 1e-6 in s and c, 1e-6 / radius in κ.
  const double h = q == Coordinate::curvature ? 1e-6 / m_tile.radius : 1e-6;
  CoarseDeformation plus = chi, minus = chi;
  double* pp = q == Coordinate::stretch ? &plus.stretch : q == Coordinate::compression ? &plus.compression : &plus.curvature;
  double* pm = q == Coordinate::stretch ? &minus.stretch : q == Coordinate::compression ? &minus.compression : &minus.curvature;
  *pp += h;
  *pm -= h;
  return (energy_with(g, plus) - energy_with(g, minus)) / (2.0 * h) / area();
}

// ---------------------------------------------------------------------------------------
// Contacts

void YarnSystem::rebuild_contacts(const Eigen::VectorXd& g) {
  m_contacts.clear();
  m_contacts_built_at = g;
  m_contacts_valid = true;
  ++m_contact_generation;
  if (!m_effects.contact) return;
  const double reach = m_contact.cutoff_distance() + m_skin;
  const double self_gap = kSelfContactArcFactor * std::max(m_params.r1, m_params.r2);
  const int ne = m_tile.edge_count();
  constexpr int kRange = kCells - 1;  // edges reach one cell further than their start

  // Boxes of every edge copy in the cells searched.
  const int side = 2 * kRange + 1;
  std::vector<Box> boxes(static_cast<std::size_t>(side * side * ne));
  std::vector<Box> cell_boxes(static_cast<std::size_t>(side * side));
  for (int ci = -kRange; ci <= kRange; ++ci) {
    for (int cj = -kRange; cj <= kRange; ++cj) {
      const int cell_index = (ci + kRange) * side + (cj + kRange);
      for (int e = 0; e < ne; ++e) {
        const auto& edge = m_tile.edges[static_cast<std::size_t>(e)];
        Box& b = boxes[static_cast<std::size_t>(cell_index * ne + e)];
        b.add(position(g, edge.v0, {ci, cj}));
        b.add(position(g, edge.v1, Cell{ci, cj} + edge.cell1));
        cell_boxes[static_cast<std::size_t>(cell_index)].add(b);
      }
    }
  }
  const int home = kRange * side + kRange;
  const Box& primary = cell_boxes[static_cast<std::size_t>(home)];
  for (int ci = -kRange; ci <= kRange; ++ci) {
    for (int cj = -kRange; cj <= kRange; ++cj) {
      const int cell_index = (ci + kRange) * side + (cj + kRange);
      if (!primary.overlaps(cell_boxes[static_cast<std::size_t>(cell_index)], reach)) continue;
      const Cell cell{ci, cj};
      const bool positive_cell = ci > 0 || (ci == 0 && cj > 0);
      for (int a = 0; a < ne; ++a) {
        const Box& ba = boxes[static_cast<std::size_t>(home * ne + a)];
        for (int b = a; b < ne; ++b) {
          if (b == a && !positive_cell) continue;
          if (!ba.overlaps(boxes[static_cast<std::size_t>(cell_index * ne + b)], reach)) continue;
          double gap = 0.0;
          if (m_tile.same_yarn_gap(a, b, cell, gap) && gap < self_gap) continue;
          m_contacts.push_back({a, b, cell});
        }
      }
    }
  }
}

bool YarnSystem::contacts_stale(const Eigen::VectorXd& g, double pending_step) const {
  if (!m_contacts_valid || m_contacts_built_at.size() != g.size()) return true;
  const Eigen::VectorXd d = g - m_contacts_built_at;
  double worst = 0.0;
  for (int v = 0; v < m_tile.vertex_count(); ++v) worst = std::max(worst, d.segment<3>(3 * v).squaredNorm());
  // Two vertices can approach by twice the largest displacement.
  return std::sqrt(worst) + pending_step > 0.5 * m_skin;
}

double YarnSystem::collision_free_fraction(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const {
  double t = 1.0;
  for (const auto& cc : m_contacts) {
    const auto& ea = m_tile.edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = m_tile.edges[static_cast<std::size_t>(cc.b)];
    const double motion = std::max(dg.segment<3>(3 * ea.v0).norm(), dg.segment<3>(3 * ea.v1).norm()) +
                          std::max(dg.segment<3>(3 * eb.v0).norm(), dg.segment<3>(3 * eb.v1).norm());
    if (motion <= 0.0) continue;
    const Cell b1 = cc.cell + eb.cell1;
    const double d = db::segment_segment_distance(
        to_point(position(g, ea.v0, {0, 0})), to_point(position(g, ea.v1, ea.cell1)),
        to_point(position(g, eb.v0, cc.cell)), to_point(position(g, eb.v1, b1)));
    if (d >= m_contact.cutoff_distance() + motion) continue;  // cannot reach the barrier
    t = std::min(t, 0.5 * d / motion);
  }
  return t;
}

double YarnSystem::min_contact_distance(const Eigen::VectorXd& g) const {
  double best = kInf;
  for (const auto& cc : m_contacts) {
    const auto& ea = m_tile.edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = m_tile.edges[static_cast<std::size_t>(cc.b)];
    const Cell b1 = cc.cell + eb.cell1;
    best = std::min(best, db::segment_segment_distance(
                              to_point(position(g, ea.v0, {0, 0})), to_point(position(g, ea.v1, ea.cell1)),
                              to_point(position(g, eb.v0, cc.cell)), to_point(position(g, eb.v1, b1))));
  }
  return best;
}

}  // namespace yarnfit::yarn
