#include "shell_fit/fit/shell_fit_report.hpp"

#include "reports/metrics/error_metrics.hpp"

#include <cmath>

namespace yarnfit::shell {

namespace {

// Eq. 6.1's six parameters, and the lock-up ones for the stiffening model.
nlohmann::json params_json(const InplaneParams& p, InplaneModel model) {
  const auto v = to_array(p);
  const int n = model == InplaneModel::stiffening ? k_inplane_param_count : k_first_lockup_param;
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < n; ++k) j[k_inplane_param_names[k]] = v[static_cast<std::size_t>(k)];
  return j;
}

}  // namespace

nlohmann::json inplane_fit_json(const InplaneFitResult& fit) {
  nlohmann::json directions = nlohmann::json::array();
  for (const auto& d : fit.directions) {
    directions.push_back({{"direction", std::string(db::to_string(d.direction))},
                          {"fitted_max_stretch", d.max_stretch},
                          {"measured_max_stretch", d.measured_max_stretch},
                          {"stretch", d.stretch},
                          {"measured_force_N", d.measured_force},
                          {"simulated_force_N", d.simulated_force},
                          {"measured_compression", d.measured_compression},
                          {"simulated_compression", d.simulated_compression}});
  }
  nlohmann::json starts = nlohmann::json::array();
  for (const auto& st : fit.starts) {
    starts.push_back({{"name", st.name},
                      {"params", params_json(st.params, fit.model)},
                      {"usable", st.ok},
                      {"cost", st.ok ? nlohmann::json(st.cost) : nlohmann::json(nullptr)},
                      {"iterations", st.iterations}});
  }
  nlohmann::json sensitivity = nlohmann::json::object();
  const int n_params = fit.model == InplaneModel::stiffening ? k_inplane_param_count : k_first_lockup_param;
  for (int k = 0; k < n_params; ++k) {
    const double v = fit.sensitivity_pct[static_cast<std::size_t>(k)];
    sensitivity[k_inplane_param_names[k]] = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  }
  nlohmann::json thesis_model = nullptr;
  if (fit.model == InplaneModel::stiffening)
    thesis_model = {{"params", params_json(fit.thesis_params, InplaneModel::thesis)},
                    {"errors",
                     {{"stretch_force_pct", reports::pct_json(fit.thesis_stretch_force_pct)},
                      {"compression_pct", fit.compression_measured ? reports::pct_json(fit.thesis_compression_pct)
                                                                   : nlohmann::json(nullptr)}}}};
  return {{"model", to_string(fit.model)},
          {"params", params_json(fit.params, fit.model)},
          {"start", params_json(fit.start, fit.model)},
          // The stiffening fit's starting point: the thesis-model fit, with its errors.
          {"thesis_model_fit", thesis_model},
          {"hit_iteration_cap", fit.hit_iteration_cap},
          {"starts", starts},
          {"chosen_start", fit.chosen_start},
          {"errors",
           {{"stretch_force_pct", reports::pct_json(fit.stretch_force_pct)},
            {"compression_pct", fit.compression_measured ? reports::pct_json(fit.compression_pct) : nlohmann::json(nullptr)}}},
          {"errors_reason", fit.errors_reason.empty() ? nlohmann::json() : nlohmann::json(fit.errors_reason)},
          // The in-plane fit's own lists and time (the top-level ones also hold the bending fit's).
          {"inplane",
           {{"timing_s", fit.seconds},
            {"not_identified", fit.not_identified},
            {"at_bounds", fit.at_bounds},
            {"compression_measured", fit.compression_measured},
            {"errors_reason", fit.errors_reason.empty() ? nlohmann::json() : nlohmann::json(fit.errors_reason)}}},
          {"identified", fit.identified},
          {"not_identified", fit.not_identified},
          {"at_bounds", fit.at_bounds},
          {"bounds", bounds_json(fit.bounds)},
          {"weakly_identified", fit.weakly_identified},
          {"sensitivity_pct_per_pct_noise", sensitivity},
          {"converged", fit.converged},
          {"message", fit.message},
          {"iterations", fit.iterations},
          {"restarts", fit.restarts},
          {"simulations", fit.simulations},
          {"directions", directions},
          {"timing_s", fit.seconds}};
}

nlohmann::json bounds_json(const std::map<std::string, std::pair<double, double>>& bounds) {
  nlohmann::json j = nlohmann::json::object();
  // The stiffnesses are searched in log space between positive bounds; the parameters searched
  // linearly (lock-up rates and shares, the stiffening law's kxy) all have a lower bound ≤ 0.
  for (const auto& [name, range] : bounds)
    j[name] = {{"lower", range.first}, {"upper", range.second}, {"log", range.first > 0.0}};
  return j;
}

}  // namespace yarnfit::shell
