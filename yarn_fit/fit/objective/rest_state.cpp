#include "yarn_fit/fit/objective/rest_state.hpp"

#include "numerics/util/clock.hpp"

namespace yarnfit::yarn {

RestState relax_rest_state(const yarn::YarnTile& tile, const yarn::YarnParams& params, const RestStateOptions& options) {
  const auto start = numerics::Clock::now();
  RestState out;
  out.params = params;
  const auto finish = [&](std::string message) {
    out.ok = message.empty();
    out.message = std::move(message);
    out.seconds = numerics::seconds_since(start);
    return out;
  };
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    return finish("invalid parameters: " + invalid.one_line());
  out.system.emplace(tile, params);
  yarn::YarnSystem& system = *out.system;
  out.g = Eigen::VectorXd::Zero(system.dof_count());
  if (options.rest_shape) {
    out.rest = relax_rest_shape(system, out.g, options.rest);
    out.newton_iterations += out.rest.newton_iterations;
    if (!out.rest.converged) return finish("rest-shape heuristic did not converge: " + out.rest.last_solve.message);
  }
  if (options.rest_period) {
    out.period = yarn::relax_rest_period(system, out.g, options.period);
    out.newton_iterations += out.period.newton_iterations;
    if (!out.period.converged) return finish("rest period did not converge: " + out.period.message);
  }
  return finish({});
}

}  // namespace yarnfit::yarn
