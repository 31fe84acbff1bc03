#include "pipeline/plan.hpp"

#include <exception>
#include <optional>

#include "exports/fitted_fabric.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/stage_plan.hpp"
#include "reports/report.hpp"

namespace yarnfit::pipeline {

namespace {

// The plan's options as the stages run them: the tile cache defaults to the output folder and
// the observer hears both fits.
PipelineOptions stage_options(const FitPlan& plan, const std::string& fabric_id, const PlanObserver& observer) {
  PipelineOptions o = plan.options;
  if (o.tile_cache.empty()) o.tile_cache = plan.out;
  if (observer) {
    o.shell.progress = [observer, fabric_id](const reports::Progress& p) { observer({Stage::shell, fabric_id, p}); };
    o.yarn.progress = [observer, fabric_id](const reports::Progress& p) { observer({Stage::yarn, fabric_id, p}); };
  }
  return o;
}

// The exports' files in the way (what the record lacks for them is the stages' check).
db::Problems export_problems(const FitPlan& plan, const db::FabricLoad& load) {
  db::Problems problems;
  for (const exports::ExportFormat format : plan.options.exports)
    problems.append(output_problems(plan.out, {exports::export_path(format, load.id).string()}, plan.overwrite));
  return problems;
}

// The plan's stages on the record `load` read, checked: `problems` gets everything that
// refuses the plan (the record's, each stage's with these `options`, every output file in the
// way). No state when the record could not be read.
std::optional<PlanState> checked_state(const FitPlan& plan, const db::FabricLoad& load, const PipelineOptions& options,
                                       const StagePlan& stages, db::Problems& problems) {
  std::optional<PlanState> state;
  problems.append(load.problems);
  if (load.ok()) {
    state = new_plan_state(*load.fabric, options);
    stages.check(*state, problems);
  } else {
    problems.append(options.problems());
  }
  problems.append(output_problems(plan.out, output_files(plan.options.stages), plan.overwrite));
  if (plan.report) problems.append(output_problems(plan.out, report_files(), plan.overwrite));
  problems.append(export_problems(plan, load));
  return state;
}

// The export stage: each format from the folder just written, into out/exports/. A fit without
// a usable shell law has nothing to export, which the text says (the fit's own status says why).
void write_exports(const FitPlan& plan, const std::string& fabric_id, PlanResult& result) {
  if (plan.options.exports.empty()) return;
  if (!result.fit.shell || !result.fit.shell->usable()) {
    result.outputs.text += "exports: none written: the shell fit has no usable law\n";
    return;
  }
  for (const exports::ExportFormat format : plan.options.exports) {
    exports::ExportRequest request;
    request.fit_dir = plan.out;
    request.format = format;
    request.out = plan.out / exports::export_path(format, fabric_id);
    request.record = plan.fabric;
    request.overwrite = true;  // checked with the plan
    try {
      const exports::ExportOutcome written = exports::export_fit(request);
      for (const auto& f : written.files) result.outputs.files.push_back(f.lexically_relative(plan.out).string());
      result.outputs.text += written.text;
    } catch (const exports::ExportError& e) {
      result.outputs.text += std::string("export ") + exports::to_string(format) + ": not written: " + e.what() + "\n";
    }
  }
}

// The report stage: out/report/ from the files just written.
void write_fit_report(const FitPlan& plan, PlanResult& result) {
  std::vector<reports::RunOutputs> runs{reports::read_fit_folders(plan.out)};
  const reports::ReportData data = reports::make_report_data(std::move(runs));
  result.report_index = reports::write_report(data, plan.out / "report");
  result.outputs.text += reports::report_written_line(data, result.report_index);
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
  (void)checked_state(plan, load, stage_options(plan, load.id, {}), StagePlan(plan.options.stages), problems);
  return problems;
}

PlanResult run_plan(const FitPlan& plan, const PlanObserver& observer, db::Problems problems) {
  PlanResult result;
  const db::FabricLoad load = db::load_fabric(plan.fabric);
  const StagePlan stages(plan.options.stages);
  std::optional<PlanState> state = checked_state(plan, load, stage_options(plan, load.id, observer), stages, problems);
  if (!problems.empty()) {
    refuse(result.fit, std::move(problems));
    return result;
  }
  result.fit = stages.run(std::move(*state));
  if (result.fit.status == PipelineStatus::invalid_input) return result;
  try {
    result.outputs = write_outputs(result.fit, plan.out);
    if (!plan.options.exports.empty() && observer) observer({Stage::exports, load.id, reports::Progress{}});
    write_exports(plan, load.id, result);  // before the report, which links them
    if (plan.report) {
      if (observer) observer({Stage::report, load.id, reports::Progress{}});
      write_fit_report(plan, result);
    }
  } catch (const std::exception& e) {
    result.write_error = plan.out.string() + ": file: " + e.what();
  }
  return result;
}

}  // namespace yarnfit::pipeline
