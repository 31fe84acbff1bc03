#pragma once
// Text reports of a shell fit, from its shell_fit.json (SPEC §5, results/shell_fit_file.hpp) only.

#include <string>

#include "results/shell_fit_file.hpp"

namespace yarnfit::reports {

// The shell part of summary.txt: errors per direction (the shell metric of each curve) and
// for all targets, bending, the parameters (and which were not fitted) and the time;
// `wall_seconds` is the stage's wall time (reading the record and writing included).
[[nodiscard]] std::string shell_summary(const results::ShellFitFile& shell_fit, double wall_seconds);

// What `yarnfit shell fit` prints when it ends: convergence, errors, the multi-start, the
// fitted ranges, identification and bound warnings, the bending fit.
[[nodiscard]] std::string shell_fit_report(const results::ShellFitFile& shell_fit);

// shell_curves.csv: direction,stretch,measured_force_N,simulated_force_N,measured_compression,
// simulated_compression, one row per target (cells left empty where a curve has no value).
[[nodiscard]] std::string shell_curves_csv(const results::ShellFitFile& shell_fit);

}  // namespace yarnfit::reports
