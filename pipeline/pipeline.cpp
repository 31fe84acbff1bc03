#include "pipeline/pipeline.hpp"

#include <cmath>
#include <stdexcept>

#include "fabrics_db/records/fabric_reader.hpp"
#include "pipeline/stage_plan.hpp"

namespace yarnfit::pipeline {

namespace {

void add_prefixed(db::Problems& out, const db::Problems& in, const std::string& prefix) {
  for (const auto& p : in.items()) out.add(p.file, p.line, prefix + p.field, p.message);
}

}  // namespace

const char* to_string(Stages stages) {
  switch (stages) {
    case Stages::shell: return "shell";
    case Stages::yarn: return "yarn";
    case Stages::all: break;
  }
  return "all";
}

bool runs_shell(Stages stages) { return stages != Stages::yarn; }
bool runs_yarn(Stages stages) { return stages != Stages::shell; }

std::optional<Stages> stages_from_string(std::string_view name) {
  if (name == "shell") return Stages::shell;
  if (name == "yarn") return Stages::yarn;
  if (name == "all") return Stages::all;
  return std::nullopt;
}

db::Problems shell_option_problems(const PipelineOptions& options) {
  db::Problems out;
  add_prefixed(out, options.shell.problems(), "shell.");
  return out;
}

db::Problems yarn_option_problems(const PipelineOptions& options) {
  calibration::YarnFitSettings checked = options.yarn;
  if (!options.start.empty()) checked.swarm = false;  // a start skips the swarm: its settings do not matter
  db::Problems out;
  add_prefixed(out, checked.problems(), "yarn.");
  return out;
}

db::Problems export_option_problems(const PipelineOptions& options) {
  db::Problems out;
  if (!options.exports.empty() && !runs_shell(options.stages))
    out.add("", 0, "export", "the formats are sampled from the fitted shell law: the shell stage must run");
  return out;
}

db::Problems PipelineOptions::problems() const {
  db::Problems out = shell_option_problems(*this);
  if (runs_yarn(stages)) out.append(yarn_option_problems(*this));
  out.append(export_option_problems(*this));
  return out;
}

db::Problems pipeline_problems(const db::Fabric& fabric, const PipelineOptions& options) {
  PlanState state = new_plan_state(fabric, options);
  db::Problems problems;
  StagePlan(options.stages).check(state, problems);
  return problems;
}

PipelineResult run_pipeline(const db::Fabric& fabric, const PipelineOptions& options) {
  PlanState state = new_plan_state(fabric, options);
  const StagePlan stages(options.stages);
  db::Problems problems;
  stages.check(state, problems);
  if (problems.empty()) return stages.run(std::move(state));
  refuse(state.result, std::move(problems));
  return std::move(state.result);
}

PipelineResult run_pipeline(const std::filesystem::path& fabric_folder, const PipelineOptions& options) {
  const db::FabricLoad load = db::load_fabric(fabric_folder);
  if (load.ok()) return run_pipeline(*load.fabric, options);
  PipelineResult result;
  result.fabric_id = load.id;
  result.fabric_folder = fabric_folder;
  db::Problems problems = load.problems;
  problems.append(options.problems());
  refuse(result, std::move(problems));
  result.message = "invalid fabric record: nothing was run";
  return result;
}

results::ShellFitFile shell_fit_file(const PipelineResult& result) {
  if (!result.shell) throw std::logic_error("shell_fit_file: the shell stage did not run");
  return shell::to_file(*result.shell);
}

results::YarnFitFile yarn_fit_file(const PipelineResult& result, const std::filesystem::path& targets_file) {
  if (!result.yarn || !result.yarn_problem) throw std::logic_error("yarn_fit_file: the yarn stage did not run");
  results::YarnFitFile f = calibration::to_file(*result.yarn_problem, *result.yarn, result.yarn_settings);
  if (result.shell) f.targets = targets_file.string();
  f.measured = result.measured;
  f.tile = result.fitted_tile_record;
  if (result.shape) {
    const calibration::ShapeFit& s = *result.shape;
    results::ShapeRecord r;
    r.aspect = s.aspect;
    r.prior = s.prior;
    r.lower = s.lower;
    r.upper = s.upper;
    r.range_lower = s.range_lower;
    r.range_upper = s.range_upper;
    r.prior_source = s.prior_source;
    r.held = s.held;
    r.wale_spacing_mm = 1e3 * s.wale_spacing;
    r.course_spacing_mm = 1e3 * s.course_spacing;
    for (const auto& t : s.trials)
      r.trials.push_back({t.aspect, t.held, std::isfinite(t.objective) ? t.objective : std::nan(""), t.r1, t.full_fit,
                          t.seconds, t.message});
    r.seconds = s.seconds;
    f.shape = std::move(r);
  }
  return f;
}

}  // namespace yarnfit::pipeline
