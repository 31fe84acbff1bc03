#include "yarn_fit/contact/contact_term.hpp"

#include <algorithm>
#include <limits>

namespace yarnfit::yarn {

double ContactTerm::max_step(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const {
  double t = 1.0;
  for (const auto& cc : m_candidates->pairs()) {
    const auto& ea = tile().edges[static_cast<std::size_t>(cc.a)];
    const auto& eb = tile().edges[static_cast<std::size_t>(cc.b)];
    const double motion = std::max(dg.segment<3>(3 * ea.v0).norm(), dg.segment<3>(3 * ea.v1).norm()) +
                          std::max(dg.segment<3>(3 * eb.v0).norm(), dg.segment<3>(3 * eb.v1).norm());
    if (motion <= 0.0) continue;
    const double d = centreline_distance(tile(), *m_placement, g, cc);
    if (d >= m_model.cutoff_distance() + motion) continue;  // cannot reach the barrier
    t = std::min(t, 0.5 * d / motion);
  }
  return t;
}

double ContactTerm::min_distance(const Eigen::VectorXd& g) const {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& cc : m_candidates->pairs()) best = std::min(best, centreline_distance(tile(), *m_placement, g, cc));
  return best;
}

}  // namespace yarnfit::yarn
