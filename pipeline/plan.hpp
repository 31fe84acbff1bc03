#pragma once
// A fit as a plan of stages (SPEC §1, §5), the one way a fit runs: the tile a knit's pattern
// names, the shell fit, its uniform targets, the yarn fit, then the files, the exports and the
// one-fabric report, each optional. `yarnfit fit`, `shell fit`, `yarn fit`, a batch job, a
// service job and a library user all run one, so there is one order of stages, one check and
// one set of output files: check_plan lists every problem before any work, run_plan checks
// the same, runs the stages with one observer and writes the folder, each file whole.
//
//   pipeline::FitPlan plan{"examples/fabrics/stockinette_demo", "out/demo"};
//   plan.options.yarn.particles = 16;  // or pipeline::fit_plan(request, problems) (fit_request.hpp)
//   plan.report = true;
//   const pipeline::PipelineResult r = pipeline::run_plan(plan, [](const pipeline::StageEvent& e) { … });
//   if (r.status == pipeline::PipelineStatus::invalid_input) std::cerr << r.problems.to_string();
//   std::cout << r.outputs.text;

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "fabrics_db/problems.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "numerics/progress.hpp"

namespace yarnfit::pipeline {

struct FitPlan {
  std::filesystem::path fabric;  // the record's folder
  // The output folder; empty: nothing is written (the result holds the stages' results only).
  std::filesystem::path out;
  // Which of shell, targets and yarn run, and their settings; a knit's generated tile is kept
  // in options.tile_cache, or in `out` when that is empty.
  PipelineOptions options;
  bool report = false;     // the one-fabric report out/report/ (what `yarnfit report out` writes)
  bool overwrite = false;  // replace output files that exist; otherwise each is a problem
  // The record itself, already read (a batch checks the record it hashed; a test edits one in
  // memory); when empty it is read from `fabric`.
  std::optional<db::Fabric> record;
};

// Progress of the stage that runs: the shell and yarn fits' events, and one when the exports
// and when the report are written.
struct StageEvent {
  Stage stage = Stage::shell;
  std::string fabric_id;
  numerics::Progress progress;
};
using PlanObserver = std::function<void(const StageEvent&)>;

// Everything run_plan would refuse, without any work: the record's problems, the options', the
// record's yarn-stage requirements, the start and targets files', and the output files that
// exist (unless overwriting).
[[nodiscard]] db::Problems check_plan(const FitPlan& plan);

// Checks, runs the stages and writes the folder (and the report when asked, also after a
// failed stage: it says why). `problems` found before (a request's, fit_request.hpp) are
// refused with the plan's. Never throws for bad input, a failed fit or a file that cannot be
// written: the result says.
PipelineResult run_plan(const FitPlan& plan, const PlanObserver& observer = {}, db::Problems problems = {});

}  // namespace yarnfit::pipeline
