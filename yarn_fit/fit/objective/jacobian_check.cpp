#include "yarn_fit/fit/objective/jacobian_check.hpp"

#include <algorithm>

#include "numerics/util/clock.hpp"

namespace yarnfit::yarn {

JacobianCheck check_residual_jacobian(const YarnObjective& objective, const RestState& rest,
                                      const yarn::YarnParams& params, std::span<const yarn::YarnParam> wanted,
                                      const std::vector<double>& relative_steps) {
  const auto start = numerics::Clock::now();
  JacobianCheck out;
  const auto finish = [&](std::string message) {
    out.ok = message.empty();
    out.message = std::move(message);
    out.seconds = numerics::seconds_since(start);
    return out;
  };
  // The centre records where its samples ended; the differences start there, so all three
  // follow one branch of equilibria (direction_sweep.hpp, warm starts).
  AtRestOptions at_centre;
  at_centre.wanted = wanted;
  at_centre.record_states = true;
  const ObjectiveResult centre = objective.evaluate_at_rest(rest, params, at_centre);
  ++out.evaluations;
  if (!centre.ok) return finish("the centre failed: " + centre.message);
  const Eigen::MatrixXd jacobian = residual_jacobian(centre);
  std::vector<SweepStates> states;
  for (const auto& d : centre.directions) states.push_back(d.states);
  AtRestOptions nearby;
  nearby.warm = &states;
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    const auto column = static_cast<Eigen::Index>(k);
    const double theta = yarn::get(params, wanted[k]);
    // In log θ: the column scaled by θ, so that every parameter's error reads alike.
    const Eigen::VectorXd analytic = jacobian.col(column) * theta;
    JacobianColumnCheck c;
    c.param = wanted[k];
    c.column_norm = analytic.lpNorm<Eigen::Infinity>();
    c.relative_error = std::numeric_limits<double>::infinity();
    for (const double rel : relative_steps) {
      yarn::YarnParams plus = params, minus = params;
      yarn::set(plus, wanted[k], theta * (1.0 + rel));
      yarn::set(minus, wanted[k], theta * (1.0 - rel));
      const ObjectiveResult rp = objective.evaluate_at_rest(rest, plus, nearby);
      const ObjectiveResult rm = objective.evaluate_at_rest(rest, minus, nearby);
      out.evaluations += 2;
      if (!rp.ok || !rm.ok) return finish(std::string("a difference of ") + yarn::to_string(wanted[k]) + " failed: " +
                                          (rp.ok ? rm.message : rp.message));
      const Eigen::VectorXd fd = (residual_vector(rp) - residual_vector(rm)) / (2.0 * rel);
      Eigen::Index worst = 0;
      const double error = (fd - analytic).cwiseAbs().maxCoeff(&worst) / std::max(c.column_norm, 1e-300);
      if (error < c.relative_error) {
        c.relative_error = error;
        c.step = rel;
        c.worst_row = worst;
      }
    }
    out.worst = std::max(out.worst, c.relative_error);
    out.columns.push_back(c);
  }
  return finish({});
}

}  // namespace yarnfit::yarn
