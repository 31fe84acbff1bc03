#pragma once
// The in-plane part of shell_fit.json (SPEC §5): params, errors, identified, timing_s — plus
// the details an engineer needs to trust the numbers (start values, per-direction curves,
// termination). Errors are null, never 0, when the final evaluation failed (`errors_reason`
// says why). The whole file, with the bending fit and effects, is to_json(ShellFitResult)
// (shell_fit/fit/shell_fit.hpp).

#include <map>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "shell_fit/fit/inplane_fit.hpp"

namespace yarnfit::shell {

nlohmann::json inplane_fit_json(const InplaneFitResult& fit);

// Search ranges as shell_fit.json's `bounds`: {name: {lower, upper, log: true}}, the form of
// yarn_fit.json's, so that a report reads both alike.
nlohmann::json bounds_json(const std::map<std::string, std::pair<double, double>>& bounds);

}  // namespace yarnfit::shell
