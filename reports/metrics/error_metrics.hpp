#pragma once
// The SPEC error metrics live in results/metrics/error_metrics.hpp: the result files carry
// them, and results sits below reports and the fits. These names keep the in-plane and bending
// fits' code (reports::ShellErrorSum) compiling while their functions are being split; new code
// includes the results header.
#include "results/metrics/error_metrics.hpp"

namespace yarnfit::reports {

using results::mean_over_directions;
using results::number_or_nan;
using results::pct_json;
using results::shell_error_pct;
using results::ShellErrorSum;
using results::yarn_error_pct;
using results::yarn_error_pct_normalised_after;

}  // namespace yarnfit::reports
