#pragma once
// The shell stage of the pipeline as one call (SPEC §1 step 2, §5 `yarnfit shell fit`): the
// in-plane fit to the stretch tests (inplane_fit.hpp), then, when the fabric has pear-loop
// tests and the in-plane fit converged, the bending fit with the in-plane model held
// (bending_fit.hpp, thesis 6.3.2), then the uniform targets of the fitted model
// (shell_fit/targets/uniform_targets.hpp) in memory. to_file gives shell_fit.json's content.
//
//   const shell::ShellFitOptions options{...};
//   if (const auto problems = options.problems(); !problems.empty()) ...;  // every bad field
//   const shell::ShellFitResult r = shell::fit_shell(fabric, options);
//   db::write_uniform_targets_csv(r.targets, dir / "uniform_targets.csv");

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "numerics/progress.hpp"
#include "results/shell_fit_file.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/fit/fab_record_fit.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::shell {

struct ShellFitOptions {
  double mesh = 5e-3;        // cell size of the clamped-stretch scenes [m], > 0
  int refinements = 0;       // midpoint subdivisions of that mesh, 0–4
  int threads = 1;           // test directions simulated in parallel, 1–64
  int max_iterations = InplaneFitOptions{}.max_iterations;  // Ceres iterations of the in-plane fit after its multi-start, 1–1000
  // Fit every measured point, not only up to the power range (83.3 N/m line force).
  bool full_range = false;
  // The in-plane law fitted (InplaneFitOptions::model; README "Choosing the shell model").
  InplaneModel model = InplaneFitOptions{}.model;
  // A FAB record's tests held out of the fit and predicted (fab_record_fit.hpp): exactly one
  // of S1 and S2, and any bends but not all three.
  std::vector<std::string> fab_held_out = k_default_fab_held_out;
  FabBendOptions fab_bends;  // the loop-bend fit of k_θ (library callers only)
  // Progress of both fits; seconds count from the start of the stage.
  numerics::ProgressFn progress;

  // Every invalid field, each named ("mesh", "refinements", …); empty when all are usable.
  [[nodiscard]] db::Problems problems() const;
};

struct ShellFitResult {
  std::string fabric_id;
  std::string family;  // the record's family (reports group by it)
  bool has_bending_tests = false;  // false: k_θ not fitted, and not identified
  InplaneFitResult inplane;
  // Set when the fabric has bending tests and the in-plane fit converged.
  std::optional<BendingFitResult> bending;
  // A FAB record's: k_θ from its loop bends (when it has no pear-loop test and the in-plane
  // fit is usable) and every test against the fitted model.
  std::optional<FabRecordFit> fab;
  ShellParams params;   // the fitted model (k_θ zero when not fitted)
  TargetRanges ranges;  // stretch and curvature ranges the targets cover
  // The uniform targets of the fitted model as uniform_targets.csv stores them
  // (db::as_stored): the yarn stage fits these, in memory or read from the file, alike.
  std::vector<db::DirectionTargets> targets;
  // What each scene simulated: "stretch" → the in-plane fit's effects, "pear_loop" → the
  // bending fit's (when it ran).
  std::map<std::string, std::vector<std::string>> effects;
  double seconds = 0.0;  // the fits (the in-plane fit's time plus the bending fit's)

  // The in-plane fit converged, and the bending fit too when it ran.
  [[nodiscard]] bool converged() const { return inplane.converged && (!bending || bending->converged) && fab_bends_converged(); }
  [[nodiscard]] bool fab_bends_converged() const {
    return !fab || std::all_of(fab->bends.begin(), fab->bends.end(), [](const FabBendFit& b) { return b.converged; });
  }
  // Converged, or the in-plane fit stopped at its iteration cap at an evaluated point (its
  // errors are those reached, and the JSON says so): later stages may use the model.
  [[nodiscard]] bool usable() const {
    return (inplane.converged || inplane.hit_iteration_cap) && (!bending || bending->converged) && fab_bends_converged();
  }
  // Why not converged ("" when converged): "shell fit did not converge: …" or "bending fit …".
  [[nodiscard]] std::string failure() const;
};

// Throws an input Error listing every problem when `options` are invalid. A fit that
// does not converge is a result (converged() false), never an exception.
ShellFitResult fit_shell(const db::Fabric& fabric, const ShellFitOptions& options);

// The result as shell_fit.json holds it (SPEC §5; results/shell_fit_file.hpp, whose to_json
// writes the file): model, params (k_θ empty when not fitted) plus, for the stiffening model,
// the lock-up pairs and shares and thesis_model_fit, errors (NaN where there is no figure, with
// errors_reason) and the errors per direction, identified, not_identified, effects, timing_s,
// the in-plane details and the bending fit's (shell_fit_output.cpp).
[[nodiscard]] results::ShellFitFile to_file(const ShellFitResult& result);

// The keys of shell_fit.json's params, in this order: eq. 6.1's six, the three k_θ, then the
// lock-up pairs and shares (absent from a thesis-model fit, where they are 0).
inline constexpr int k_shell_param_count = 17;
inline const char* const k_shell_param_names[k_shell_param_count] = {
    "kxx", "kxy", "kyy", "kss", "kn1", "kn2", "ktheta_weft", "ktheta_bias", "ktheta_warp",
    "lxx", "bxx", "lyy", "byy", "lss", "bss", "axx", "ayy"};

// The parameters of a shell_fit.json (its `params`, or the top level when there is none), in
// the order of k_shell_param_names; absent and null (not fitted) ones are empty. Problems
// name the file and the key (unreadable, not JSON, a value that is not a number, none found).
std::array<std::optional<double>, k_shell_param_count> read_shell_params(const std::filesystem::path& file, db::Problems& problems);

}  // namespace yarnfit::shell
