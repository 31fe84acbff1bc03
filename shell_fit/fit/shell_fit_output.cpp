// The shell stage's result as shell_fit.json holds it (results/shell_fit_file.hpp): the in-plane
// fit's figures and details, the bending fit's, and the per-direction errors, computed here once.
#include "shell_fit/fit/shell_fit.hpp"

#include <cmath>
#include <limits>

#include "fabrics_db/text_util.hpp"
#include "results/metrics/error_metrics.hpp"

namespace yarnfit::shell {

namespace {

// Eq. 6.1's six parameters, and the lock-up ones for the stiffening model.
std::map<std::string, double> param_values(const InplaneParams& p, InplaneModel model) {
  const auto v = to_array(p);
  const int n = model == InplaneModel::stiffening ? k_inplane_param_count : k_first_lockup_param;
  std::map<std::string, double> out;
  for (int k = 0; k < n; ++k) out[k_inplane_param_names[k]] = v[static_cast<std::size_t>(k)];
  return out;
}

// The stiffnesses are searched in log space between positive bounds; the parameters searched
// linearly (lock-up rates and shares, the stiffening law's kxy) all have a lower bound ≤ 0.
void add_bounds(const std::map<std::string, std::pair<double, double>>& bounds,
                std::map<std::string, results::SearchBound>& out) {
  for (const auto& [name, range] : bounds) out[name] = {range.first, range.second, range.first > 0.0};
}

void append(std::vector<std::string>& to, const std::vector<std::string>& more) {
  to.insert(to.end(), more.begin(), more.end());
}

// The loop bends' k_θ as the fitted bending parameters. errors.bending_pct stays the pear-loop
// aspect ratio's (none here): the bends' force errors are per direction and in `fab`.
void add_fab_bends(const FabRecordFit& fab, results::ShellFitFile& f) {
  std::vector<std::string> fitted;
  for (const auto& b : fab.bends) {
    const auto k = static_cast<std::size_t>(b.direction);
    if (!(b.ktheta > 0.0) || b.tests.empty()) {
      f.not_identified.push_back(std::string(k_bending_names[k]) + ": " + b.message);
      continue;
    }
    f.params[k_bending_names[k]] = b.ktheta;
    fitted.push_back(k_bending_names[k]);
    if (b.on_bound) f.at_bounds.push_back(k_bending_names[k]);
    if (b.ktheta_high > 2.0 * b.ktheta_low)
      f.weakly_identified.push_back(std::string(k_bending_names[k]) + ": the loop bends fit within twice the best misfit from " +
                                    db::format_g(b.ktheta_low, 2) + " to " + db::format_g(b.ktheta_high, 2) +
                                    " N*m (each test's zero free)");
  }
  std::string names;
  for (const auto& name : fitted) names += (names.empty() ? "" : ", ") + name;
  if (!names.empty()) f.identified.push_back(names + ": from the FAB's loop-method bends (force against clamp distance)");
}

// Every FAB test against the model, and the fitted tests' figures in errors_by_direction.
void add_fab_tests(const FabRecordFit& fab, results::ShellFitFile& f) {
  results::FabFitDetails details;
  details.held_out = fab.held_out;
  details.timing_s = fab.seconds;
  for (const auto& b : fab.bends)
    details.bends.push_back({std::string(db::to_string(b.direction)), b.ktheta, b.ktheta_low, b.ktheta_high, b.force_pct,
                             b.converged, b.on_bound,
                             b.evaluations, b.seconds, b.message});
  for (const auto& t : fab.tests) {
    const std::string dir(db::to_string(t.direction));
    const FabTestError& e = t.error;
    details.tests.push_back({dir, e.test, t.held_out, e.samples, e.force_pct, e.first_cycles_force_pct, e.mean_abs_error,
                             e.offset, t.cycles.spread_pct, t.cycles.hysteresis_pct, e.converged, e.message});
  }
  // The fitted stretch test against every measured loading branch, and the fitted bends'
  // force error, stand for the direction; the held-out tests stand apart.
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const auto entry = [&f](const std::string& dir) -> results::ShellDirectionErrors& {
    return f.errors_by_direction.try_emplace(dir, results::ShellDirectionErrors{nan, nan, nan}).first->second;
  };
  for (const auto& b : fab.bends) entry(std::string(db::to_string(b.direction))).bending_pct = b.force_pct;
  for (const auto& t : details.tests)
    if (!t.held_out && t.test[0] == 'S' && t.converged) entry(t.direction).stretch_force_pct = t.force_pct;
  f.timing_s += fab.seconds;
  f.fab = std::move(details);
}

}  // namespace

results::ShellFitFile to_file(const ShellFitResult& r) {
  const InplaneFitResult& fit = r.inplane;
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  results::ShellFitFile f;
  f.fabric = r.fabric_id;
  f.family = r.family;
  f.model = to_string(fit.model);
  for (const auto& [name, value] : param_values(fit.params, fit.model)) f.params[name] = value;
  for (const char* k : k_bending_names) f.params[k] = std::nullopt;
  f.start = param_values(fit.start, fit.model);
  if (fit.model == InplaneModel::stiffening)
    f.thesis_model_fit = results::ThesisModelFit{param_values(fit.thesis_params, InplaneModel::thesis),
                                                 fit.thesis_stretch_force_pct,
                                                 fit.compression_measured ? fit.thesis_compression_pct : nan};
  f.hit_iteration_cap = fit.hit_iteration_cap;
  for (const auto& st : fit.starts)
    f.starts.push_back({st.name, param_values(st.params, fit.model), st.ok, st.ok ? st.cost : nan, st.iterations});
  f.chosen_start = fit.chosen_start;
  f.errors = {fit.stretch_force_pct, fit.compression_measured ? fit.compression_pct : nan, nan};
  f.errors_reason = fit.errors_reason;
  f.inplane = results::InplaneDetails{fit.seconds, fit.not_identified, fit.at_bounds, fit.compression_measured,
                                      fit.errors_reason};
  f.identified = fit.identified;
  f.not_identified = fit.not_identified;
  f.at_bounds = fit.at_bounds;
  add_bounds(fit.bounds, f.bounds);
  f.weakly_identified = fit.weakly_identified;
  const int n_params = fit.model == InplaneModel::stiffening ? k_inplane_param_count : k_first_lockup_param;
  for (int k = 0; k < n_params; ++k)
    f.sensitivity_pct_per_pct_noise[k_inplane_param_names[k]] = fit.sensitivity_pct[static_cast<std::size_t>(k)];
  f.converged = fit.converged;
  f.message = fit.message;
  f.iterations = fit.iterations;
  f.restarts = fit.restarts;
  f.simulations = fit.simulations;
  for (const auto& d : fit.directions)
    f.directions.push_back({std::string(db::to_string(d.direction)), d.max_stretch, d.measured_max_stretch, d.stretch,
                            d.measured_force, d.simulated_force, d.measured_compression, d.simulated_compression});
  f.timing_s = fit.seconds;
  f.effects = r.effects;

  std::string bending_reason;
  const bool fab_bends = r.fab && !r.fab->bends.empty();
  if (!r.has_bending_tests && !fab_bends) {
    f.not_identified.push_back("ktheta_weft, ktheta_bias, ktheta_warp: no bending test (not fitted)");
  } else if (fab_bends) {
    add_fab_bends(*r.fab, f);
  } else if (!r.bending) {
    bending_reason = "bending not fitted: the in-plane fit did not converge";
  } else {
    const BendingFitResult& b = *r.bending;
    for (std::size_t k = 0; k < 3; ++k) f.params[k_bending_names[k]] = b.params.ktheta[k];
    f.errors.bending_pct = b.bending_pct;
    append(f.identified, b.identified);
    append(f.not_identified, b.not_identified);
    append(f.at_bounds, b.at_bounds);
    add_bounds(b.bounds, f.bounds);
    results::BendingDetails details{b.converged, b.message, b.iterations, b.simulations, b.seconds, b.at_bounds,
                                    {}, b.not_identified, b.fallback_starts, b.errors_reason};
    for (const auto& d : b.directions)
      details.curves.push_back({std::string(db::to_string(d.direction)), d.clamp_distance, d.measured_aspect_ratio,
                                d.simulated_aspect_ratio});
    f.bending = details;
    if (!b.errors_reason.empty()) bending_reason = "bending: " + b.errors_reason;
    f.timing_s = fit.seconds + b.seconds;
  }
  // One line for every null figure: the in-plane fit's reason first.
  if (!bending_reason.empty()) f.errors_reason = fit.errors_reason.empty() ? bending_reason : fit.errors_reason + "; " + bending_reason;
  f.errors_by_direction = results::shell_direction_errors(f.directions, f.bending);
  if (r.fab) add_fab_tests(*r.fab, f);
  return f;
}

}  // namespace yarnfit::shell
