#pragma once
// shell_fit.json (SPEC §5): params, errors, identified, effects, timing_s — plus the details
// an engineer needs to trust the numbers (start values, per-direction curves, termination).

#include <nlohmann/json.hpp>

#include "shell_fit/fit/inplane_fit.hpp"

namespace yarnfit::shell {

nlohmann::json inplane_fit_json(const InplaneFitResult& fit);

}  // namespace yarnfit::shell
