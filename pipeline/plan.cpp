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

// The plan's record: the one it holds, or the one its folder holds (with the reader's problems).
db::FabricLoad record_of(const FitPlan& plan) {
  if (!plan.record) return db::load_fabric(plan.fabric);
  db::FabricLoad load;
  load.folder = plan.record->folder.empty() ? plan.fabric : plan.record->folder;
  load.id = plan.record->id;
  load.family = plan.record->family;
  load.fabric = plan.record;
  return load;
}

// What runs once the stages ran: nothing for a plan without an output folder.
OutputStages outputs_of(const FitPlan& plan) { return plan.out.empty() ? OutputStages{} : output_stages(plan); }

}  // namespace

db::Problems check_plan(const FitPlan& plan) {
  const db::FabricLoad load = record_of(plan);
  db::Problems problems;
  (void)checked_state(plan, load, stage_options(plan, load.id, {}), StagePlan(plan.options.stages), outputs_of(plan),
                      problems);
  return problems;
}

PipelineResult run_plan(const FitPlan& plan, const PlanObserver& observer, db::Problems problems) {
  const db::FabricLoad load = record_of(plan);
  const StagePlan stages(plan.options.stages);
  const OutputStages outputs = outputs_of(plan);
  std::optional<PlanState> state =
      checked_state(plan, load, stage_options(plan, load.id, observer), stages, outputs, problems);
  if (!problems.empty()) {
    PipelineResult refused;
    refused.fabric_id = load.id;
    refused.fabric_folder = plan.fabric;
    refuse(refused, std::move(problems));
    return refused;
  }
  PipelineResult result = stages.run(std::move(*state));
  if (result.status == PipelineStatus::invalid_input) return result;
  try {
    for (const auto& output : outputs) output->run(plan, load.id, result, observer);
  } catch (const std::exception& e) {
    result.write_error = plan.out.string() + ": file: " + e.what();
  }
  return result;
}

}  // namespace yarnfit::pipeline
