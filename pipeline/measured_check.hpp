#pragma once
// A fitted yarn model checked against the record's measured curves (issue 48, item 4): the
// yarn stage fits uniform targets, which a shell law made from the measurements; whether the
// yarn model reproduces the measurements themselves is a question of its own.
//
//   1. the model's own uniform responses: the final evaluation's stretch stress σ_s and free
//      compression c* at every sample of each direction, and the bending check's Δσ_κ(κ);
//   2. homogenised back: the shell law of the shell stage's kind fitted to them
//      (shell::fit_law_to_samples, from the shell stage's law when there is one); its misfit
//      says how much of what follows is the law's and not the yarn model's;
//   3. the record's clamped-stretch and pear-loop scenes run with that law
//      (shell::simulate_record_errors): the errors against every measured curve, per test and
//      direction, in the shell fit's metric and names.

#include <optional>

#include "yarn_fit/fit/yarn_fit.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "results/yarn_fit_file.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/fit/record_errors.hpp"

namespace yarnfit::pipeline {

// The model's uniform responses as uniform targets (σ_s first Piola-Kirchhoff, as the targets
// are), per direction of the final evaluation and of the bending check.
[[nodiscard]] std::vector<db::DirectionTargets> yarn_model_samples(const yarn::YarnFitResult& yarn);

// Steps 2 and 3 for a fit that ended ok. `start` (the shell stage's law) seeds the law's fit.
// Never throws for numerical trouble: the record says what failed.
[[nodiscard]] results::MeasuredCheckRecord check_against_measurements(const db::Fabric& fabric,
                                                                      const yarn::YarnFitResult& yarn,
                                                                      shell::InplaneModel model,
                                                                      const std::optional<shell::InplaneParams>& start,
                                                                      const shell::RecordErrorOptions& options = {});

}  // namespace yarnfit::pipeline
