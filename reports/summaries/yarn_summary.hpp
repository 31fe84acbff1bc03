#pragma once
// Text reports of a yarn fit, from its yarn_fit.json (SPEC §5) only: the summary (errors per
// direction, parameters with their bounds, the identifiability profile, time per stage) and
// the curves of the fitted model beside its targets.

#include <string>

#include "results/yarn_fit_file.hpp"

namespace yarnfit::reports {

// yarn_summary.txt's body and the yarn part of summary.txt.
[[nodiscard]] std::string yarn_summary(const results::YarnFitFile& yarn_fit);

// yarn_curves.csv: per direction and stretch sample of the final evaluation, target and
// simulated second Piola-Kirchhoff stress S = σ_s/(1+s) [N/m], zero-orthogonal-stress
// compression and weight (from yarn_fit.json's `curves`).
[[nodiscard]] std::string yarn_curves_csv(const results::YarnFitFile& yarn_fit);

}  // namespace yarnfit::reports
