#include "swarm/cobyla.hpp"
#include "numerics/util/error.hpp"

#include <stdexcept>
#include <string>

namespace yarnfit::swarm {

CobylaSummary run_cobyla(const ParameterSpace& space, const Objective& objective, const Eigen::VectorXd& start,
                         const CobylaSettings& settings) {
  numerics::Problems problems = settings.problems();
  if (!(settings.initial_step <= 1.0)) problems.add_field("initial_step", "must be in (0, 1] (fraction of the range)");
  if (!(settings.x_tolerance < 1.0)) problems.add_field("x_tolerance", "must be in [0, 1)");
  if (!problems.empty()) throw Error(ErrorCategory::input, "cobyla settings: " + problems.one_line());
  Eigen::VectorXd u;
  try {
    u = space.to_unit(start);
  } catch (const Error& e) {
    throw with_context("cobyla start: ", e);
  }
  const int n = space.dimension();
  const Objective in_unit_cube = [&](const Eigen::VectorXd& unit) { return objective(space.from_unit(unit)); };
  CobylaSummary s = numerics::run_cobyla(in_unit_cube, u, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Ones(n), settings);
  s.best_point = space.from_unit(s.best_point);
  for (auto& f : s.failures) f.x = space.from_unit(f.x);
  return s;
}

}  // namespace yarnfit::swarm
