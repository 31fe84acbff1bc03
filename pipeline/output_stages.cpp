#include "pipeline/output_stages.hpp"

#include "exports/fitted_fabric.hpp"
#include "numerics/util/error.hpp"
#include "reports/report.hpp"

namespace yarnfit::pipeline {

namespace {

// The stages' files: shell_fit.json … summary.txt (outputs.hpp), each written whole.
class WriteStage final : public OutputStage {
 public:
  void check(const FitPlan& plan, const db::FabricLoad&, db::Problems& problems) const override {
    problems.append(output_problems(plan.out, output_files(plan.options.stages), plan.overwrite));
  }
  void run(const FitPlan& plan, const std::string&, PipelineResult& result, const PlanObserver&) const override {
    result.outputs = write_outputs(result, plan.out);
  }
};

// Each format from the folder just written, into out/exports/ (exports::export_path). A fit
// without a usable shell law has nothing to export, which the text says (the fit's own status
// says why); a format that cannot be written says why and the others go on.
class ExportStage final : public OutputStage {
 public:
  void check(const FitPlan& plan, const db::FabricLoad& load, db::Problems& problems) const override {
    for (const exports::ExportFormat format : plan.options.exports)
      problems.append(output_problems(plan.out, {exports::export_path(format, load.id).string()}, plan.overwrite));
  }
  void run(const FitPlan& plan, const std::string& fabric_id, PipelineResult& result,
           const PlanObserver& observer) const override {
    if (observer) observer({Stage::exports, fabric_id, numerics::Progress{}});
    if (!result.shell || !result.shell->usable()) {
      result.outputs.text += "exports: none written: the shell fit has no usable law\n";
      return;
    }
    for (const exports::ExportFormat format : plan.options.exports) {
      exports::ExportRequest request;
      request.fit_dir = plan.out;
      request.format = format;
      request.out = plan.out / exports::export_path(format, fabric_id);
      request.record = plan.fabric;
      request.tile_cache = plan.options.tile_cache.empty() ? plan.out : plan.options.tile_cache;
      request.overwrite = true;  // checked with the plan
      try {
        const exports::ExportOutcome written = exports::export_fit(request);
        for (const auto& f : written.files) result.outputs.files.push_back(f.lexically_relative(plan.out).string());
        result.outputs.text += written.text;
      } catch (const Error& e) {
        if (!e.users_to_mend()) throw;  // a file that cannot be written fails the run, as the writer's do
        result.outputs.text += request.out.string() + ": not written: " + e.what() + "\n";
      }
    }
  }
};

// out/report/ from the files just written.
class ReportStage final : public OutputStage {
 public:
  void check(const FitPlan& plan, const db::FabricLoad&, db::Problems& problems) const override {
    problems.append(output_problems(plan.out, report_files(), plan.overwrite));
  }
  void run(const FitPlan& plan, const std::string& fabric_id, PipelineResult& result,
           const PlanObserver& observer) const override {
    if (observer) observer({Stage::report, fabric_id, numerics::Progress{}});
    std::vector<reports::RunOutputs> runs{reports::read_fit_folders(plan.out)};
    // The report lies in the folder it describes: its name says enough, and a fit run for
    // someone else (the service's) shows nothing of where the server keeps it.
    runs.front().source = plan.out.filename();
    const reports::ReportData data = reports::make_report_data(std::move(runs));
    result.report_index = reports::write_report(data, plan.out / "report");
    result.outputs.text += reports::report_written_line(data, result.report_index);
  }
};

}  // namespace

std::vector<std::unique_ptr<OutputStage>> output_stages(const FitPlan& plan) {
  std::vector<std::unique_ptr<OutputStage>> stages;
  stages.push_back(std::make_unique<WriteStage>());
  if (!plan.options.exports.empty()) stages.push_back(std::make_unique<ExportStage>());
  if (plan.report) stages.push_back(std::make_unique<ReportStage>());
  return stages;
}

}  // namespace yarnfit::pipeline
