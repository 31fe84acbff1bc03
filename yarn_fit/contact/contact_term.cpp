#include "yarn_fit/contact/contact_term.hpp"

#include <algorithm>
#include <limits>

#include "numerics/geometry/segment_distance.hpp"

namespace yarnfit::yarn {
namespace {

numerics::Point3 to_point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

double ContactTerm::max_step(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const {
  double t = 1.0;
  for (const auto& cc : m_candidates->pairs()) {
    const auto& ea = tile().edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = tile().edges[static_cast<std::size_t>(cc.b)];
    const double motion = std::max(dg.segment<3>(3 * ea.v0).norm(), dg.segment<3>(3 * ea.v1).norm()) +
                          std::max(dg.segment<3>(3 * eb.v0).norm(), dg.segment<3>(3 * eb.v1).norm());
    if (motion <= 0.0) continue;
    const Cell b1 = cc.cell + eb.cell1;
    const double d = numerics::segment_segment_distance(
        to_point(m_placement->position(g, ea.v0, {0, 0})), to_point(m_placement->position(g, ea.v1, ea.cell1)),
        to_point(m_placement->position(g, eb.v0, cc.cell)), to_point(m_placement->position(g, eb.v1, b1)));
    if (d >= m_model.cutoff_distance() + motion) continue;  // cannot reach the barrier
    t = std::min(t, 0.5 * d / motion);
  }
  return t;
}

double ContactTerm::min_distance(const Eigen::VectorXd& g) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& cc : m_candidates->pairs()) {
    const auto& ea = tile().edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = tile().edges[static_cast<std::size_t>(cc.b)];
    const Cell b1 = cc.cell + eb.cell1;
    best = std::min(best, numerics::segment_segment_distance(
                              to_point(m_placement->position(g, ea.v0, {0, 0})),
                              to_point(m_placement->position(g, ea.v1, ea.cell1)),
                              to_point(m_placement->position(g, eb.v0, cc.cell)),
                              to_point(m_placement->position(g, eb.v1, b1))));
  }
  return best;
}

}  // namespace yarnfit::yarn
