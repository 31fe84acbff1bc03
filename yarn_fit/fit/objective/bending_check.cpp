#include "yarn_fit/fit/objective/bending_check.hpp"

#include <cmath>

#include "yarn_fit/fit/objective/rest_state.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/terms/scene.hpp"
#include "numerics/util/clock.hpp"
#include "results/metrics/error_metrics.hpp"

namespace yarnfit::yarn {

BendingCheck check_bending(const yarn::YarnTile& tile, const std::vector<db::DirectionTargets>& targets,
                           const yarn::YarnParams& params, const ObjectiveOptions& options, int points) {
  const auto start = numerics::Clock::now();
  BendingCheck out;
  auto finish = [&](std::string message) {
    out.ok = message.empty();
    out.message = std::move(message);
    out.seconds = numerics::seconds_since(start);
    return out;
  };
  bool any = false;
  for (const auto& t : targets) any = any || t.bending.size() >= 2;
  if (!any) return finish({});
  if (points < 2) return finish("bending check: points must be at least 2");
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    return finish("invalid parameters: " + invalid.one_line());

  // The rest state the objective relaxes for these parameters (rest_state.hpp).
  const RestState rest = relax_rest_state(tile, params, {options.rest_shape, options.rest, options.rest_period, options.period});
  if (!rest.ok) return finish(rest.message);
  const yarn::YarnSystem& relaxed = *rest.system;
  const Eigen::VectorXd& g_rest = rest.g;
  std::vector<double> per_direction;
  for (const auto& t : targets) {
    if (t.bending.size() < 2) continue;
    const std::string dname(db::to_string(t.direction));
    BendingDirectionError e;
    e.direction = t.direction;
    yarn::YarnSystem system = relaxed;
    Eigen::VectorXd g = g_rest;
    yarn::CoarseDeformation chi;
    chi.angle = db::pull_angle(t.direction);
    const yarn::BendingSample flat = yarn::simulate_bending(system, chi, g, 0.0, options.solve);
    out.solves += flat.centre.solves;
    numerics::merge_effects(out.effects, flat.centre.effects);
    if (!flat.ok) return finish(dname + ": bending at κ = 0 failed: " + flat.message);
    e.curl_stress = flat.stress_kappa;
    const std::size_t m = t.bending.size();
    double largest = 0.0;
    for (const auto& b : t.bending) largest = std::max(largest, std::abs(b.stress));
    for (int k = 0; k < points; ++k) {
      const std::size_t i = static_cast<std::size_t>(std::lround(static_cast<double>(k) * static_cast<double>(m - 1) / (points - 1)));
      chi.curvature = t.bending[i].curvature;
      double sigma = flat.stress_kappa;
      if (chi.curvature != 0.0) {
        const yarn::BendingSample bs = yarn::simulate_bending(system, chi, g, 0.0, options.solve);
        out.solves += bs.centre.solves;
        numerics::merge_effects(out.effects, bs.centre.effects);
        if (!bs.ok) return finish(dname + ": bending at κ = " + db::format_g(chi.curvature) + " 1/m failed: " + bs.message);
        sigma = bs.stress_kappa;
      }
      e.curvature.push_back(chi.curvature);
      e.stress_sim.push_back(sigma - flat.stress_kappa);
      e.stress_target.push_back(t.bending[i].stress);
    }
    e.error_pct = results::yarn_error_pct_normalised_after(e.stress_sim, e.stress_target, largest);
    per_direction.push_back(e.error_pct);
    out.directions.push_back(std::move(e));
  }
  out.bending_pct = results::mean_over_directions(per_direction);
  return finish({});
}

}  // namespace yarnfit::yarn
