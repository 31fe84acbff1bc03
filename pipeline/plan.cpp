#include "pipeline/plan.hpp"

#include <exception>
#include <optional>

#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/output_stages.hpp"
#include "pipeline/stage_plan.hpp"

namespace yarnfit::pipeline {

namespace {

using OutputStages = std::vector<std::unique_ptr<OutputStage>>;

// The plan's options as the stages run them: the tile cache defaults to the output folder and
// the observer hears both fits.
PipelineOptions stage_options(const FitPlan& plan, const std::string& fabric_id, const PlanObserver& observer) {
  PipelineOptions o = plan.options;
  if (o.tile_cache.empty()) o.tile_cache = plan.out;
  if (observer) {
    o.shell.progress = [observer, fabric_id](const numerics::Progress& p) { observer({Stage::shell, fabric_id, p}); };
    o.yarn.progress = [observer, fabric_id](const numerics::Progress& p) { observer({Stage::yarn, fabric_id, p}); };
  }
  return o;
}

// The plan's stages on the record `load` read, checked: `problems` gets everything that
// refuses the plan (the record's, each stage's with these `options`, every output file in the
// way). No state when the record could not be read.
std::optional<PlanState> checked_state(const FitPlan& plan, const db::FabricLoad& load, const PipelineOptions& options,
                                       const StagePlan& stages, const OutputStages& outputs, db::Problems& problems) {
  std::optional<PlanState> state;
  problems.append(load.problems);
  if (load.ok()) {
    state = new_plan_state(*load.fabric, options);
    stages.check(*state, problems);
  } else {
    problems.append(options.problems());
  }
  for (const auto& output : outputs) output->check(plan, load, problems);
  return state;
}

}  // namespace

const char* to_string(Stage stage) {
  switch (stage) {
    case Stage::tile: return "tile";
    case Stage::shell: return "shell";
    case Stage::targets: return "targets";
    case Stage::yarn: return "yarn";
    case Stage::exports: return "export";
    case Stage::report: return "report";
  }
  return "?";
}

db::Problems check_plan(const FitPlan& plan) {
  const db::FabricLoad load = db::load_fabric(plan.fabric);
  db::Problems problems;
  (void)checked_state(plan, load, stage_options(plan, load.id, {}), StagePlan(plan.options.stages), output_stages(plan),
                      problems);
  return problems;
}

PlanResult run_plan(const FitPlan& plan, const PlanObserver& observer, db::Problems problems) {
  PlanResult result;
  const db::FabricLoad load = db::load_fabric(plan.fabric);
  const StagePlan stages(plan.options.stages);
  const OutputStages outputs = output_stages(plan);
  std::optional<PlanState> state =
      checked_state(plan, load, stage_options(plan, load.id, observer), stages, outputs, problems);
  if (!problems.empty()) {
    refuse(result.fit, std::move(problems));
    return result;
  }
  result.fit = stages.run(std::move(*state));
  if (result.fit.status == PipelineStatus::invalid_input) return result;
  try {
    for (const auto& output : outputs) output->run(plan, load.id, result, observer);
  } catch (const std::exception& e) {
    result.write_error = plan.out.string() + ": file: " + e.what();
  }
  return result;
}

}  // namespace yarnfit::pipeline
