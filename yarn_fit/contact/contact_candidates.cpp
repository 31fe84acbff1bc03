#include "yarn_fit/contact/contact_candidates.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "numerics/geometry/segment_distance.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {
namespace {

using numerics::k_inf;

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(k_inf);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-k_inf);
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

}  // namespace

double centreline_distance(const YarnTile& tile, const TilePlacement& placement, const Eigen::VectorXd& g,
                           const ContactCandidate& pair) {
  const auto point = [&](int v, const Cell& c) {
    const Eigen::Vector3d x = placement.position(g, v, c);
    return numerics::Point3{x.x(), x.y(), x.z()};
  };
  const auto& ea = tile.edges[static_cast<std::size_t>(pair.a)];
  const auto& eb = tile.edges[static_cast<std::size_t>(pair.b)];
  return numerics::segment_segment_distance(point(ea.v0, {0, 0}), point(ea.v1, ea.cell1), point(eb.v0, pair.cell),
                                            point(eb.v1, pair.cell + eb.cell1));
}

void ContactCandidates::rebuild(const YarnTile& tile, const TilePlacement& placement, const Eigen::VectorXd& g,
                                double cutoff, double skin, double radius, bool find_pairs) {
  m_pairs.clear();
  m_built_at = g;
  m_valid = true;
  m_skin = skin;
  ++m_generation;
  if (!find_pairs) return;
  const double reach = cutoff + skin;
  const double self_gap = kSelfContactArcFactor * radius;
  const int ne = tile.edge_count();
  constexpr int kRange = TilePlacement::kCells - 1;  // edges reach one cell further than their start

  // Boxes of every edge copy in the cells searched.
  const int side = 2 * kRange + 1;
  std::vector<Box> boxes(static_cast<std::size_t>(side * side * ne));
  std::vector<Box> cell_boxes(static_cast<std::size_t>(side * side));
  for (int ci = -kRange; ci <= kRange; ++ci) {
    for (int cj = -kRange; cj <= kRange; ++cj) {
      const int cell_index = (ci + kRange) * side + (cj + kRange);
      for (int e = 0; e < ne; ++e) {
        const auto& edge = tile.edges[static_cast<std::size_t>(e)];
        Box& b = boxes[static_cast<std::size_t>(cell_index * ne + e)];
        b.add(placement.position(g, edge.v0, {ci, cj}));
        b.add(placement.position(g, edge.v1, Cell{ci, cj} + edge.cell1));
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
          if (tile.same_yarn_gap(a, b, cell, gap) && gap < self_gap) continue;
          // Boxes overlap for about twice as many pairs as come within reach (stockinette at
          // 30 % weft: 34 % of the box candidates were farther than the cutoff plus skin,
          // rib 46 %), and every energy, gradient, Hessian and step bound visits each pair.
          // A pair dropped here keeps zero energy until the list goes stale, as the skin
          // argument above says; the margin covers the distance's rounding.
          if (centreline_distance(tile, placement, g, {a, b, cell}) > reach * (1.0 + 1e-9)) continue;
          m_pairs.push_back({a, b, cell});
        }
      }
    }
  }
}

bool ContactCandidates::stale(const Eigen::VectorXd& g, double pending_step) const {
  if (!m_valid || m_built_at.size() != g.size()) return true;
  const Eigen::VectorXd d = g - m_built_at;
  double worst = 0.0;
  for (Eigen::Index v = 0; v < d.size() / 3; ++v) worst = std::max(worst, d.segment<3>(3 * v).squaredNorm());
  // Two vertices can approach by twice the largest displacement.
  return std::sqrt(worst) + pending_step > 0.5 * m_skin;
}

}  // namespace yarnfit::yarn
