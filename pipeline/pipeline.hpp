#pragma once
// The whole pipeline for one fabric as a library call (SPEC §1, §5 `yarnfit fit`): the shell
// stage (shell_fit/fit/shell_fit.hpp) fits the shell model and makes the uniform targets,
// which go in memory to the yarn stage (calibration/problem/yarn_fit_problem.hpp). Everything
// that could refuse the run — options, the record's yarn-fit requirements, the --start file —
// is checked before the shell stage starts, and every problem is listed.
//
//   pipeline::PipelineOptions options;
//   options.yarn.particles = 16;
//   const auto result = pipeline::run_pipeline("examples/fabrics/stockinette_demo", options);
//   if (result.status == pipeline::PipelineStatus::invalid_input) std::cerr << result.problems.to_string();
//   pipeline::write_pipeline_outputs(result, "out/stockinette_demo");

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibration/fit/yarn_calibration.hpp"
#include "calibration/problem/shape_search.hpp"
#include "calibration/problem/yarn_fit_problem.hpp"
#include "exports/export_fit.hpp"
#include "results/yarn_fit_file.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/fit/shell_fit.hpp"

namespace yarnfit::pipeline {

// Which stages run: the shell fit and its uniform targets only, the yarn fit alone on targets
// read from a file, or the whole pipeline.
enum class Stages { shell, yarn, all };
[[nodiscard]] const char* to_string(Stages stages);  // "shell", "yarn", "all"
[[nodiscard]] bool runs_shell(Stages stages);
[[nodiscard]] bool runs_yarn(Stages stages);
[[nodiscard]] std::optional<Stages> stages_from_string(std::string_view name);

struct PipelineOptions {
  Stages stages = Stages::all;
  shell::ShellFitOptions shell;
  calibration::YarnFitSettings yarn;
  // The shape of a tile generated without a gauge, fitted with the yarn parameters.
  calibration::ShapeSearchSettings shape;
  // Parameters the yarn fit's local step starts from (empty: none); the swarm is then skipped,
  // whatever yarn.swarm says (calibration::settings_for).
  std::filesystem::path start;
  // Stages::yarn: the uniform targets the yarn stage fits (uniform_targets.csv as the shell
  // stage writes it).
  std::filesystem::path targets;
  // The formats the fitted fabric is exported to once the fit is written (stage "export",
  // exports/export_fit.hpp), beside its other outputs (exports::export_path).
  std::vector<exports::ExportFormat> exports;
  // Where tiles generated for records whose pattern names a knit are kept and looked up
  // (calibration/problem/generated_pattern.hpp); required for such records.
  std::filesystem::path tile_cache;

  // Every invalid field, named "shell.<field>" or "yarn.<field>" (shell::ShellFitOptions,
  // calibration::YarnFitSettings; the yarn settings only when the yarn stage runs); empty
  // when both are usable.
  [[nodiscard]] db::Problems problems() const;
};

enum class PipelineStatus {
  ok,
  invalid_input,  // nothing ran: `problems` lists why
  shell_failed,   // the shell fit did not converge: no yarn fit
  yarn_failed,    // the yarn fit ran and failed (it still has a result)
};

struct PipelineResult {
  PipelineStatus status = PipelineStatus::invalid_input;
  db::Problems problems;  // invalid_input: every problem found before any work
  std::string message;    // why the status is not ok
  std::string fabric_id;
  std::filesystem::path fabric_folder;  // as given (summary.txt names it)
  std::optional<shell::ShellFitResult> shell;
  std::optional<calibration::YarnFitProblem> yarn_problem;  // its targets are the shell stage's
  std::optional<calibration::YarnFitResult> yarn;
  // The fitted yarn model against the record's measured curves (pipeline/measured_check.hpp),
  // when the yarn fit ended ok.
  std::optional<results::MeasuredCheckRecord> measured;
  // The tile's shape, when it was fitted (calibration/problem/shape_search.hpp).
  std::optional<calibration::ShapeFit> shape;
  // The tile the yarn model was fitted on (the shape's, the generated one, the record's), as
  // the output folder's tile.pyp holds it.
  std::optional<db::PeriodicTile> fitted_tile;
  std::optional<results::FittedTileRecord> fitted_tile_record;  // yarn_fit.json's `tile` (pipeline/fitted_tile.hpp)
  calibration::YarnFitSettings yarn_settings;  // as given (the problem's start applied by the fit)
  Stages stages = Stages::all;
  double seconds_shell = 0.0;  // from the start (the record read) to the shell stage's end
  double seconds_yarn = 0.0;
  double seconds_total = 0.0;
};

// Everything run_pipeline would refuse for this fabric: the options' problems, the record's
// (no pattern, no yarn stiffness, an unusable tile: only when the yarn stage runs), the start
// file's and the targets file's. Fast: no simulation.
[[nodiscard]] db::Problems pipeline_problems(const db::Fabric& fabric, const PipelineOptions& options);

// Runs the stages on `fabric` (with Stages::shell the result is ok once the shell fit
// converged or stopped at its iteration cap with a usable model (ShellFitResult::usable, said
// in shell_fit.json; `message` then says why it did not converge), and has no yarn problem or
// result; with Stages::yarn there is no shell result). Never throws for bad input or a failed fit:
// the status says.
PipelineResult run_pipeline(const db::Fabric& fabric, const PipelineOptions& options);
// The same on the record in `fabric_folder` (read and validated first; its problems are the
// result's when it is invalid).
PipelineResult run_pipeline(const std::filesystem::path& fabric_folder, const PipelineOptions& options);

// The stages' results as their files hold them (SPEC §5; results/). yarn_fit.json names its
// targets `targets_file`: the file the shell stage's targets are written to.
results::ShellFitFile shell_fit_file(const PipelineResult& result);
// With Stages::yarn the targets are the file the options name, whatever `targets_file` says.
results::YarnFitFile yarn_fit_file(const PipelineResult& result, const std::filesystem::path& targets_file);

}  // namespace yarnfit::pipeline
