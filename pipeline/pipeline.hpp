#pragma once
// The options and the result of a fit of one fabric (SPEC §1, §5): the shell stage
// (shell_fit/fit/shell_fit.hpp) fits the shell model and makes the uniform targets, which go
// in memory to the yarn stage (yarn_fit/fit/problem/yarn_fit_problem.hpp). A fit runs one way,
// as a plan (pipeline/plan.hpp: check_plan, run_plan), whoever asks for it: the command line,
// a batch job, the service, a library user.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "yarn_fit/fit/yarn_fit.hpp"
#include "yarn_fit/fit/problem/shape_search.hpp"
#include "yarn_fit/fit/problem/yarn_fit_problem.hpp"
#include "exports/export_fit.hpp"
#include "results/yarn_fit_file.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/fit/shell_fit.hpp"

namespace yarnfit::pipeline {

// The stages of a fit in the order they run (a plan's events name the one running), and what
// a fit is asked to run: `all` of them, or the shell or the yarn fit alone (the yarn fit then
// on targets read from a file). exports and report run after the fit when the plan asks.
enum class Stage { all, tile, shell, targets, yarn, exports, report };
[[nodiscard]] const char* to_string(Stage stage);  // "all", "tile", "shell", …, "export", "report"
// Whether a fit asked to run `stages` (all, shell or yarn) runs the shell and the yarn fit.
[[nodiscard]] bool runs_shell(Stage stages);
[[nodiscard]] bool runs_yarn(Stage stages);
// What a user may ask to run: "all", "shell" or "yarn"; nullopt for anything else.
[[nodiscard]] std::optional<Stage> stages_from_string(std::string_view name);

struct PipelineOptions {
  Stage stages = Stage::all;  // all, shell or yarn
  shell::ShellFitOptions shell;
  yarn::YarnFitSettings yarn;
  // The shape of a tile generated without a gauge, fitted with the yarn parameters.
  yarn::ShapeSearchSettings shape;
  // Parameters the yarn fit's local step starts from (empty: none); the swarm is then skipped,
  // whatever yarn.swarm says (yarn::settings_for).
  std::filesystem::path start;
  // Stage::yarn: the uniform targets the yarn stage fits (uniform_targets.csv as the shell
  // stage writes it).
  std::filesystem::path targets;
  // The formats the fitted fabric is exported to once the fit is written (stage "export",
  // exports/export_fit.hpp), beside its other outputs (exports::export_path).
  std::vector<exports::ExportFormat> exports;
  // Where tiles generated for records whose pattern names a knit are kept and looked up
  // (yarn_fit/fit/problem/generated_pattern.hpp); required for such records.
  std::filesystem::path tile_cache;

  // Every invalid field, named "stages", "shell.<field>" or "yarn.<field>"
  // (shell::ShellFitOptions, yarn::YarnFitSettings; the yarn settings only when the
  // yarn stage runs); empty when both are usable.
  [[nodiscard]] db::Problems problems() const;
};

enum class PipelineStatus {
  ok,
  invalid_input,  // nothing ran: `problems` lists why
  shell_failed,   // the shell fit did not converge: no yarn fit
  yarn_failed,    // the yarn fit ran and failed (it still has a result)
};

// What the plan wrote (write_outputs and the exports and report after it).
struct PipelineOutputs {
  std::vector<std::string> files;  // names written into the folder, in order
  std::string summary;             // summary.txt or yarn_summary.txt's summary (empty when the yarn stage did not run)
  // What a terminal shows of them: the shell stage's report, the summary and where the files
  // are.
  std::string text;
};

// A fit's result: its status, the stages' results and the files written.
struct PipelineResult {
  PipelineStatus status = PipelineStatus::invalid_input;
  db::Problems problems;  // invalid_input: every problem found before any work
  std::string message;    // why the status is not ok
  std::string fabric_id;
  std::filesystem::path fabric_folder;  // as given (summary.txt names it)
  std::optional<shell::ShellFitResult> shell;
  std::optional<yarn::YarnFitProblem> yarn_problem;  // its targets are the shell stage's
  std::optional<yarn::YarnFitResult> yarn;
  // The fitted yarn model against the record's measured curves (pipeline/measured_check.hpp),
  // when the yarn fit ended ok.
  std::optional<results::MeasuredCheckRecord> measured;
  // The tile's shape, when it was fitted (yarn_fit/fit/problem/shape_search.hpp).
  std::optional<yarn::ShapeFit> shape;
  // The tile the yarn model was fitted on (the shape's, the generated one, the record's), as
  // the output folder's tile.pyp holds it.
  std::optional<db::PeriodicTile> fitted_tile;
  std::optional<results::FittedTileRecord> fitted_tile_record;  // yarn_fit.json's `tile` (pipeline/fitted_tile.hpp)
  yarn::YarnFitSettings yarn_settings;  // as given (the problem's start applied by the fit)
  Stage stages = Stage::all;
  double seconds_shell = 0.0;  // from the start (the record read) to the shell stage's end
  double seconds_yarn = 0.0;
  double seconds_total = 0.0;

  // The output folder (none for a plan without one).
  PipelineOutputs outputs;             // the files written and the text a terminal shows of them
  std::filesystem::path report_index;  // out/report/index.html when the report was written
  std::string write_error;             // a file that could not be written (the run then stops there)
  [[nodiscard]] bool ok() const { return status == PipelineStatus::ok && write_error.empty(); }
};

// The stages' results as their files hold them (SPEC §5; results/). yarn_fit.json names its
// targets `targets_file`: the file the shell stage's targets are written to.
results::ShellFitFile shell_fit_file(const PipelineResult& result);
// With Stage::yarn the targets are the file the options name, whatever `targets_file` says.
results::YarnFitFile yarn_fit_file(const PipelineResult& result, const std::filesystem::path& targets_file);

}  // namespace yarnfit::pipeline
