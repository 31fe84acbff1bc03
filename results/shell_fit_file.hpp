#pragma once
// shell_fit.json (SPEC §5 `yarnfit shell fit`) as a type: what the shell stage wrote, read back
// by the reports, the summaries, batch and the CLI without knowing a JSON key. The shell fit
// fills it (shell::to_file, shell_fit/fit/shell_fit.hpp); to_json writes the file and
// shell_fit_file_from_json reads it, of this version or an older one.
//
// Schema versions:
//   1  no `schema_version` key (every file before the results module);
//   2  `schema_version` 2 and `errors_by_direction` {weft|bias|warp: {stretch_force_pct,
//      compression_pct, bending_pct}}: the shell metric of each direction's curves, computed
//      once by the fit. Reading a version-1 file computes them from its curves, the same way
//      (the same numbers to the last bit: JSON keeps doubles exactly).
//
// "No figure" (a failed evaluation, nothing measured) is NaN here and null in the file.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "results/search_bound.hpp"

namespace yarnfit::results {

inline constexpr int k_shell_fit_schema_version = 2;

// The shell metric over all targets [%]; NaN: no figure.
struct ShellErrors {
  double stretch_force_pct = 0.0;
  double compression_pct = 0.0;
  double bending_pct = 0.0;  // the pear-loop aspect ratio; NaN when not fitted
};

// One stretch test's targets and the model's values there.
struct ShellDirectionCurves {
  std::string direction;              // weft, bias or warp
  double fitted_max_stretch = 0.0;    // end of the fitted range
  double measured_max_stretch = 0.0;  // end of the measured curve
  std::vector<double> stretch;
  std::vector<double> measured_force_N;
  std::vector<double> simulated_force_N;      // empty when the final evaluation failed
  std::vector<double> measured_compression;   // empty when not measured
  std::vector<double> simulated_compression;
};

// One start of the in-plane multi-start.
struct ShellStart {
  std::string name;
  std::map<std::string, double> params;
  bool usable = false;
  double cost = 0.0;  // NaN when not usable
  int iterations = 0;
};

// The stiffening fit's starting point: the thesis-model fit and its errors.
struct ThesisModelFit {
  std::map<std::string, double> params;
  double stretch_force_pct = 0.0;
  double compression_pct = 0.0;
};

// The in-plane fit's own lists and time (the top-level ones also hold the bending fit's).
struct InplaneDetails {
  double timing_s = 0.0;
  std::vector<std::string> not_identified;
  std::vector<std::string> at_bounds;
  bool compression_measured = true;
  std::string errors_reason;  // empty: there are errors
};

// One pear-loop test's targets and the model's aspect ratios there.
struct BendingCurve {
  std::string direction;
  std::vector<double> clamp_distance_m;
  std::vector<double> measured_aspect_ratio;
  std::vector<double> simulated_aspect_ratio;  // empty when the final evaluation failed
};

// The bending fit (thesis 6.3.2), when it ran.
struct BendingDetails {
  bool converged = false;
  std::string message;
  int iterations = 0;
  int simulations = 0;
  double timing_s = 0.0;
  std::vector<std::string> at_bounds;
  std::vector<BendingCurve> curves;
  std::vector<std::string> not_identified;
  std::vector<std::string> fallback_starts;
  std::string errors_reason;  // empty: there is a bending figure
};

// The shell metric of one direction's curves [%]; NaN where it has no such curve or no figure.
struct ShellDirectionErrors {
  double stretch_force_pct = 0.0;
  double compression_pct = 0.0;
  double bending_pct = 0.0;  // the aspect ratio of its pear-loop test
};

// One test of a FAB record against the fitted model (a FAB record's fit; docs/fab.md).
struct FabTestResult {
  std::string direction;
  std::string test;        // S1, S2, U1, D1, D2
  bool held_out = false;   // predicted, not fitted
  int samples = 0;         // loading-branch samples compared
  double force_pct = 0.0;  // over every loading branch [%]; NaN: no figure
  double first_cycles_force_pct = 0.0;  // a stretch test's, within its first two cycles' range
  double mean_abs_error_N = 0.0;
  double offset_N = 0.0;        // taken off the readings: the zero (stretch) or the fitted offset (bend)
  double spread_pct = 0.0;      // the measurement's loading branches apart where they overlap
  double hysteresis_pct = 0.0;  // the measurement's: loop area over loading work
  bool converged = false;
  std::string message;
};

// The loop-bend fit of one direction's k_θ.
struct FabBendResult {
  std::string direction;
  double ktheta = 0.0;  // [N·m]
  double ktheta_low = 0.0, ktheta_high = 0.0;  // where the misfit doubles [N·m]
  double force_pct = 0.0;
  bool converged = false;
  bool on_bound = false;
  int evaluations = 0;
  double timing_s = 0.0;
  std::string message;
};

struct FabFitDetails {
  std::vector<std::string> held_out;  // the tests predicted, not fitted
  std::vector<FabBendResult> bends;
  std::vector<FabTestResult> tests;
  double timing_s = 0.0;
};

struct ShellFitFile {
  int schema_version = k_shell_fit_schema_version;  // as read; to_json writes the current one
  std::string fabric;
  std::string family;
  std::string model = "thesis";  // the in-plane law: thesis (eq. 6.1) or stiffening
  // Fitted values by name (kxx … kn2, ktheta_*, and the stiffening law's); empty: not fitted.
  std::map<std::string, std::optional<double>> params;
  std::map<std::string, double> start;  // the balanced start
  std::optional<ThesisModelFit> thesis_model_fit;  // stiffening fits only
  bool hit_iteration_cap = false;
  std::vector<ShellStart> starts;
  int chosen_start = -1;  // index into starts
  ShellErrors errors;
  std::map<std::string, ShellDirectionErrors> errors_by_direction;  // by direction name
  std::string errors_reason;  // why figures are missing; empty when none is
  std::optional<InplaneDetails> inplane;  // absent from the oldest files
  std::vector<std::string> identified;
  std::vector<std::string> not_identified;
  std::vector<std::string> at_bounds;
  std::map<std::string, SearchBound> bounds;
  std::vector<std::string> weakly_identified;
  std::map<std::string, double> sensitivity_pct_per_pct_noise;  // NaN: none
  bool converged = false;
  std::string message;
  int iterations = 0;
  int restarts = 0;
  int simulations = 0;
  std::vector<ShellDirectionCurves> directions;
  double timing_s = 0.0;  // both fits
  std::map<std::string, std::vector<std::string>> effects;  // scene → effects simulated
  std::optional<BendingDetails> bending;
  std::optional<FabFitDetails> fab;  // a FAB record's fit (its `fab` block)

  // The direction's errors, all NaN when the file has none for it.
  [[nodiscard]] ShellDirectionErrors direction_errors(const std::string& direction) const;
};

// The per-direction errors of a file's curves: the shell metric of each stretch test's force and
// compression and of each pear-loop test's aspect ratio (results/metrics/error_metrics.hpp).
[[nodiscard]] std::map<std::string, ShellDirectionErrors> shell_direction_errors(
    const std::vector<ShellDirectionCurves>& directions, const std::optional<BendingDetails>& bending);

namespace detail {
class Where;  // results/json_fields.hpp
}

// A stretch test's curves, a pear-loop test's curves and a direction's shell errors as
// shell_fit.json writes and reads them (yarn_fit.json's check against the measurements too).
[[nodiscard]] nlohmann::json curves_json(const ShellDirectionCurves& d);
[[nodiscard]] ShellDirectionCurves read_curves(const nlohmann::json& d, const detail::Where& at);
[[nodiscard]] nlohmann::json bending_curve_json(const BendingCurve& c);
[[nodiscard]] BendingCurve read_bending_curve(const nlohmann::json& c, const detail::Where& at);
[[nodiscard]] nlohmann::json direction_errors_json(const std::map<std::string, ShellDirectionErrors>& errors);
[[nodiscard]] ShellDirectionErrors read_shell_errors(const nlohmann::json& e, const detail::Where& at);

// The figures of `errors` under their names in the file (stretch_force_pct, compression_pct,
// bending_pct), for tables whose columns take those names (the batch ledger, SPEC §5).
[[nodiscard]] std::map<std::string, double> named_errors(const ShellErrors& errors);
// The fitted parameters as the file's `params` object (null: not fitted).
[[nodiscard]] nlohmann::json params_json(const std::map<std::string, std::optional<double>>& params);

// shell_fit.json of the current schema version.
[[nodiscard]] nlohmann::json to_json(const ShellFitFile& file);

// A shell_fit.json of any version. Fields added since a version default when absent; a field of
// the wrong type throws an Error naming it ("shell_fit.json: directions[0].stretch:
// expected …"), as does a file that is not an object or lacks `params`.
// `source` names the file in messages.
[[nodiscard]] ShellFitFile shell_fit_file_from_json(const nlohmann::json& json,
                                                   const std::string& source = "shell_fit.json");

// The file at `path`; throws an Error naming it when it cannot be read or parsed.
[[nodiscard]] ShellFitFile read_shell_fit_file(const std::filesystem::path& path);

}  // namespace yarnfit::results
