#pragma once
// A shell law against a record's measured tests, nothing fitted (issue 48): the record's
// clamped-stretch tests simulated at the shell fit's own targets (6 per test, up to the power
// range unless `full_range`) and its pear-loop tests at the bending fit's distances, compared
// with the measured curves in the shell fit's metric and names (stretch_force_pct,
// compression_pct, bending_pct; results/metrics). A yarn model homogenised back to a law
// (uniform_law_fit.hpp) is checked against the measurements this way.

#include <map>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "results/shell_fit_file.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

struct RecordErrorOptions {
  double mesh = 5e-3;          // clamped-stretch cells [m], as the shell fit's
  double bending_mesh = 2.5e-3;  // pear-loop cells [m], as the bending fit's
  bool full_range = false;     // every measured point, not only up to the power range
};

struct RecordErrors {
  bool ok = false;
  std::string message;  // the first scene that failed
  results::ShellErrors errors;  // over all targets; NaN where there is no figure
  std::map<std::string, results::ShellDirectionErrors> by_direction;
  std::vector<results::ShellDirectionCurves> curves;  // the stretch tests' targets and the law's values
  std::vector<results::BendingCurve> bending;          // the pear-loop tests' targets and the law's values
  double seconds = 0.0;
};

// Throws an input Error for a record with bending tests and no areal density.
RecordErrors simulate_record_errors(const db::Fabric& fabric, const ShellParams& params,
                                    const RecordErrorOptions& options = {});

}  // namespace yarnfit::shell
