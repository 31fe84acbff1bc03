#include "shell_fit/fit/shell_fit_report.hpp"

#include "reports/metrics/error_metrics.hpp"

namespace yarnfit::shell {

namespace {

nlohmann::json params_json(const InplaneParams& p) {
  return {{"kxx", p.kxx}, {"kxy", p.kxy}, {"kyy", p.kyy}, {"kss", p.kss}, {"kn1", p.kn1}, {"kn2", p.kn2}};
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
                      {"params", params_json(st.params)},
                      {"usable", st.ok},
                      {"cost", st.ok ? nlohmann::json(st.cost) : nlohmann::json(nullptr)},
                      {"iterations", st.iterations}});
  }
  return {{"params", params_json(fit.params)},
          {"start", params_json(fit.start)},
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
          {"sensitivity_pct_per_pct_noise",
           {{"kxx", fit.sensitivity_pct[0]}, {"kxy", fit.sensitivity_pct[1]}, {"kyy", fit.sensitivity_pct[2]},
            {"kss", fit.sensitivity_pct[3]}, {"kn1", fit.sensitivity_pct[4]}, {"kn2", fit.sensitivity_pct[5]}}},
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
  for (const auto& [name, range] : bounds) j[name] = {{"lower", range.first}, {"upper", range.second}, {"log", true}};
  return j;
}

}  // namespace yarnfit::shell
