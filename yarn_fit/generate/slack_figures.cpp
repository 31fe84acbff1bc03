#include "yarn_fit/generate/slack_figures.hpp"

#include <algorithm>
#include <cmath>

#include "yarn_fit/periodic/coarse_map.hpp"

namespace yarnfit::yarn {

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::floor(q * static_cast<double>(values.size() - 1) + 0.5);
  return values[static_cast<std::size_t>(std::clamp(rank, 0.0, static_cast<double>(values.size() - 1)))];
}

double SlackFigures::median_iterations() const { return quantile(iterations, 0.5); }
double SlackFigures::max_iterations() const { return quantile(iterations, 1.0); }
double SlackFigures::consistency_median() const { return quantile(consistency, 0.5); }
double SlackFigures::consistency_90th() const { return quantile(consistency, 0.9); }

bool SlackFigures::meets(const SlackGoals& goals) const {
  return points > 0 && converged == points && median_iterations() <= goals.median_iterations &&
         max_iterations() <= goals.max_iterations && consistency_median() <= goals.consistency_median &&
         consistency_90th() <= goals.consistency_90th;
}

SlackFigures sweep_slack_tile(const YarnTile& tile, const YarnParams& params, const Eigen::VectorXd& rest) {
  SlackFigures f;
  for (const auto& [angle, direction] : {std::pair{weft_angle(), "weft"}, {bias_angle(), "bias"}, {warp_angle(), "warp"}}) {
    YarnSystem system(tile, params);
    Eigen::VectorXd g = rest;
    SlackDirection d{direction, sweep_stretch(system, angle, even_stretches(0.22, 23), g)};
    const std::vector<Sample>& points = d.sweep.points;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Sample& s = points[i];
      f.converged += s.ok ? 1 : 0;
      f.iterations.push_back(s.newton_iterations);
      if (i == 0 || !s.ok || !points[i - 1].ok || points[i - 1].chi.stretch < 0.05 - 1e-12) continue;
      const Sample& before = points[i - 1];
      const double d_psi = s.energy_density - before.energy_density;
      const double trapezoid = 0.5 * (s.stress_s + before.stress_s) * (s.chi.stretch - before.chi.stretch);
      f.consistency.push_back(std::abs(d_psi - trapezoid) / std::max(std::abs(d_psi), 1e-300));
    }
    f.points += static_cast<int>(points.size());
    f.seconds += d.sweep.seconds;
    f.directions.push_back(std::move(d));
  }
  return f;
}

}  // namespace yarnfit::yarn
