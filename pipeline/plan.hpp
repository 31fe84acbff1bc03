#pragma once
// A fit as a plan of stages (SPEC §1, §5): the tile a knit's pattern names, the shell fit, its
// uniform targets, the yarn fit and the one-fabric report, each optional. `yarnfit fit`,
// `shell fit`, `yarn fit`, a batch job and a service job all run one, so there is one order of
// stages and one set of output files: check_plan lists every problem before any work,
// run_plan runs the stages with one observer and writes the folder, each file whole.
//
//   pipeline::FitPlan plan{"examples/fabrics/stockinette_demo", "out/demo"};
//   plan.options = pipeline::pipeline_options(request, problems);  // pipeline/fit_request.hpp
//   plan.report = true;
//   const pipeline::PlanResult r = pipeline::run_plan(plan, [](const pipeline::StageEvent& e) { … });
//   std::cout << r.outputs.text;

#include <filesystem>
#include <functional>
#include <string>

#include "fabrics_db/problems.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "numerics/progress.hpp"

namespace yarnfit::pipeline {

// The stages in the order they run.
enum class Stage { tile, shell, targets, yarn, exports, report };
[[nodiscard]] const char* to_string(Stage stage);

struct FitPlan {
  std::filesystem::path fabric;  // the record's folder
  std::filesystem::path out;     // the output folder
  // Which of shell, targets and yarn run, and their settings; a knit's generated tile is kept
  // in options.tile_cache, or in `out` when that is empty.
  PipelineOptions options;
  bool report = false;     // the one-fabric report out/report/ (what `yarnfit report out` writes)
  bool overwrite = false;  // replace output files that exist; otherwise each is a problem
};

// Progress of the stage that runs: the shell and yarn fits' events, and one when the exports
// and when the report are written.
struct StageEvent {
  Stage stage = Stage::shell;
  std::string fabric_id;
  numerics::Progress progress;
};
using PlanObserver = std::function<void(const StageEvent&)>;

struct PlanResult {
  PipelineResult fit;       // status, problems and message of the stages
  PipelineOutputs outputs;  // the files written and the text a terminal shows of them
  std::filesystem::path report_index;  // out/report/index.html when the report was written
  std::string write_error;  // a file that could not be written (the run then stops there)
  [[nodiscard]] bool ok() const { return fit.status == PipelineStatus::ok && write_error.empty(); }
};

// Everything run_plan would refuse, without any work: the record's problems, the options', the
// record's yarn-stage requirements, the start and targets files', and the output files that
// exist (unless overwriting).
[[nodiscard]] db::Problems check_plan(const FitPlan& plan);

// Checks, runs the stages and writes the folder (and the report when asked, also after a
// failed stage: it says why). `problems` found before (a request's, fit_request.hpp) are
// refused with the plan's. Never throws for bad input, a failed fit or a file that cannot be
// written: the result says.
PlanResult run_plan(const FitPlan& plan, const PlanObserver& observer = {}, db::Problems problems = {});

}  // namespace yarnfit::pipeline
