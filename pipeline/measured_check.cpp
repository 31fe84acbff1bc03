#include "pipeline/measured_check.hpp"

#include <exception>

#include "numerics/util/clock.hpp"
#include "shell_fit/fit/uniform_law_fit.hpp"

namespace yarnfit::pipeline {

std::vector<db::DirectionTargets> yarn_model_samples(const yarn::YarnFitResult& yarn) {
  std::vector<db::DirectionTargets> out;
  const auto entry = [&out](db::Direction d) -> db::DirectionTargets& {
    for (auto& t : out)
      if (t.direction == d) return t;
    out.push_back({d, {}, {}});
    return out.back();
  };
  for (const auto& d : yarn.final.directions) {
    db::DirectionTargets& t = entry(d.scale.direction);
    // The objective holds the second Piola-Kirchhoff S = σ_s / (1 + s); the targets σ_s.
    for (std::size_t i = 0; i < d.stretch.size(); ++i)
      t.stretch.push_back({d.stretch[i], d.compression_sim[i], d.stress_sim[i] * (1.0 + d.stretch[i]), true});
  }
  for (const auto& b : yarn.bending.directions) {
    db::DirectionTargets& t = entry(b.direction);
    for (std::size_t i = 0; i < b.curvature.size(); ++i) t.bending.push_back({b.curvature[i], b.stress_sim[i]});
  }
  return out;
}

results::MeasuredCheckRecord check_against_measurements(const db::Fabric& fabric, const yarn::YarnFitResult& yarn,
                                                        shell::InplaneModel model,
                                                        const std::optional<shell::InplaneParams>& start,
                                                        const shell::RecordErrorOptions& options) {
  const auto clock = numerics::Clock::now();
  results::MeasuredCheckRecord out;
  out.law_model = shell::to_string(model);
  const auto finish = [&](std::string message) {
    out.message = std::move(message);
    out.seconds = numerics::seconds_since(clock);
    return out;
  };
  if (!yarn.ok) return finish("the yarn fit failed: nothing to check");
  const shell::UniformLawFit law = shell::fit_law_to_samples(yarn_model_samples(yarn), model, start);
  if (!law.ok) return finish("the yarn model's samples could not be homogenised to a shell law: " + law.message);
  const auto values = shell::to_array(law.params.inplane);
  const int n = model == shell::InplaneModel::stiffening ? shell::k_inplane_param_count : shell::k_first_lockup_param;
  for (int k = 0; k < n; ++k) out.law_params[shell::k_inplane_param_names[k]] = values[static_cast<std::size_t>(k)];
  const char* const ktheta[3] = {"ktheta_weft", "ktheta_bias", "ktheta_warp"};
  for (std::size_t k = 0; k < 3; ++k) out.law_params[ktheta[k]] = law.params.bending.ktheta[k];
  out.law_stress_misfit_pct = law.stress_misfit_pct;
  out.law_compression_misfit_pct = law.compression_misfit_pct;
  out.law_bending_misfit_pct = law.bending_misfit_pct;
  // A record with bending tests but no bending samples (the check was skipped) has no k_θ to
  // run its pear loops with: only its stretch tests are simulated then.
  db::Fabric tested = fabric;
  if (yarn.bending.directions.empty()) tested.bending_tests.clear();
  try {
    const shell::RecordErrors errors = shell::simulate_record_errors(tested, law.params, options);
    out.ok = errors.ok;
    out.all = errors.errors;
    out.by_direction = errors.by_direction;
    out.curves = errors.curves;
    out.bending_curves = errors.bending;
    std::string message = errors.message;
    if (tested.bending_tests.size() != fabric.bending_tests.size())
      message += std::string(message.empty() ? "" : "; ") + "no bending samples from the yarn fit: pear loops not simulated";
    return finish(message);
  } catch (const std::exception& e) {
    return finish(std::string("the record's scenes could not run: ") + e.what());
  }
}

}  // namespace yarnfit::pipeline
