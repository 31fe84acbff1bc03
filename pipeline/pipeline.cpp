#include "pipeline/pipeline.hpp"

#include <stdexcept>

#include "calibration/problem/generated_pattern.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "numerics/util/clock.hpp"

namespace yarnfit::pipeline {

namespace {

using numerics::Clock;
using numerics::seconds_since;


void add_prefixed(db::Problems& out, const db::Problems& in, const std::string& prefix) {
  for (const auto& p : in.items()) out.add(p.file, p.line, prefix + p.field, p.message);
}

// The yarn problem of the fabric (no targets yet), every problem added to `problems`.
std::optional<calibration::YarnFitProblem> yarn_problem(const db::Fabric& fabric, const PipelineOptions& options,
                                                        db::Problems& problems) {
  auto problem = calibration::make_yarn_fit_problem(fabric, problems);
  if (problem && !options.start.empty())
    calibration::read_start(*problem, options.start, options.yarn.linear_stretch, problems);
  return problem;
}

// A record whose pattern is a knit whose tile the yarn stage must generate first.
bool tile_to_generate(const db::Fabric& fabric) {
  return fabric.pattern && fabric.pattern->knit && !fabric.pattern->has_tile();
}

// What can be checked of such a record before its tile exists.
void check_generated_pattern(const db::Fabric& fabric, const PipelineOptions& options, db::Problems& problems) {
  if (options.tile_cache.empty())
    problems.add("", 0, "tile_cache", "the pattern is a knit to generate: say where generated tiles are kept");
  calibration::check_yarn_stiffness(fabric, problems);
}


// Stage 1: the shell fit and its uniform targets. False when the pipeline ends here.
bool run_shell_stage(const db::Fabric& fabric, const PipelineOptions& options, PipelineResult& result,
                     Clock::time_point start) {
  result.shell = shell::fit_shell(fabric, options.shell);
  result.seconds_shell = seconds_since(start);
  if (!result.shell->converged()) result.message = result.shell->failure();
  if (!result.shell->usable()) {
    result.status = PipelineStatus::shell_failed;
    return false;
  }
  result.status = PipelineStatus::ok;
  return runs_yarn(options.stages);
}

// Stage 2: the yarn fit on the shell stage's targets, handed over in memory (as the file holds
// them), or on the targets file's (read by prepare_fit).
void run_yarn_stage(const PipelineOptions& options, std::vector<db::DirectionTargets> file_targets,
                    PipelineResult& result) {
  const auto yarn_start = Clock::now();
  auto& problem = *result.yarn_problem;
  if (result.shell) {
    problem.targets = result.shell->targets;
  } else {
    problem.targets = std::move(file_targets);
    problem.targets_source = options.targets.string();
  }
  try {
    result.yarn = calibration::fit_yarn(problem, options.yarn);
    result.status = result.yarn->ok ? PipelineStatus::ok : PipelineStatus::yarn_failed;
    result.message = result.yarn->ok ? std::string() : "yarn fit failed: " + result.yarn->message;
  } catch (const std::invalid_argument& e) {
    // The settings were checked: the targets cannot be fitted.
    const std::string source = result.shell ? "the shell stage's uniform targets" : options.targets.string();
    result.status = result.shell ? PipelineStatus::yarn_failed : PipelineStatus::invalid_input;
    result.message = source + ": " + e.what();
    if (!result.shell) result.problems.add(options.targets.string(), 0, "targets", e.what());
  }
  result.seconds_yarn = seconds_since(yarn_start);
}

PipelineResult run(PreparedFit prepared, const PipelineOptions& options, Clock::time_point start) {
  PipelineResult result;
  db::Fabric& fabric = prepared.fabric;
  result.fabric_id = fabric.id;
  result.fabric_folder = fabric.folder;
  result.yarn_settings = options.yarn;
  result.stages = options.stages;
  result.problems = std::move(prepared.problems);
  result.yarn_problem = std::move(prepared.yarn_problem);
  if (result.problems.empty() && runs_yarn(options.stages) && tile_to_generate(fabric)) {
    // The stage "tile": a knit's tile is generated now that nothing else stands in the way.
    calibration::make_generated_pattern(fabric, options.tile_cache, result.problems);
    if (result.problems.empty()) result.yarn_problem = yarn_problem(fabric, options, result.problems);
  }
  if (!result.problems.empty()) {
    result.status = PipelineStatus::invalid_input;
    result.message = "invalid input: nothing was run";
    result.yarn_problem.reset();
    return result;
  }
  const bool yarn_next = !runs_shell(options.stages) || run_shell_stage(fabric, options, result, start);
  if (yarn_next) run_yarn_stage(options, std::move(prepared.targets).value_or(std::vector<db::DirectionTargets>{}), result);
  result.seconds_total = seconds_since(start);
  return result;
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

db::Problems PipelineOptions::problems() const {
  db::Problems out;
  add_prefixed(out, shell.problems(), "shell.");
  if (!runs_yarn(stages)) return out;
  calibration::YarnFitSettings checked = yarn;
  if (!start.empty()) checked.swarm = false;  // a start skips the swarm: its settings do not matter
  add_prefixed(out, checked.problems(), "yarn.");
  return out;
}

PreparedFit prepare_fit(const db::Fabric& fabric, const PipelineOptions& options) {
  PreparedFit out{fabric, std::nullopt, std::nullopt, options.problems()};
  if (!runs_yarn(options.stages)) return out;
  if (tile_to_generate(fabric)) check_generated_pattern(fabric, options, out.problems);
  else out.yarn_problem = yarn_problem(fabric, options, out.problems);
  if (options.stages == Stages::yarn) {
    if (options.targets.empty()) out.problems.add("", 0, "targets", "the yarn stage alone needs a targets file");
    else out.targets = db::read_uniform_targets(options.targets, out.problems);
  }
  return out;
}

db::Problems pipeline_problems(const db::Fabric& fabric, const PipelineOptions& options) {
  return prepare_fit(fabric, options).problems;
}

PipelineResult run_prepared(PreparedFit prepared, const PipelineOptions& options) {
  return run(std::move(prepared), options, Clock::now());
}

PipelineResult run_pipeline(const db::Fabric& fabric, const PipelineOptions& options) {
  const auto start = Clock::now();
  return run(prepare_fit(fabric, options), options, start);
}

PipelineResult run_pipeline(const std::filesystem::path& fabric_folder, const PipelineOptions& options) {
  const auto start = Clock::now();
  const db::FabricLoad load = db::load_fabric(fabric_folder);
  if (!load.ok()) {
    PipelineResult result;
    result.status = PipelineStatus::invalid_input;
    result.message = "invalid fabric record: nothing was run";
    result.fabric_id = load.id;
    result.fabric_folder = fabric_folder;
    result.problems = load.problems;
    result.problems.append(options.problems());
    return result;
  }
  return run(prepare_fit(*load.fabric, options), options, start);
}

results::ShellFitFile shell_fit_file(const PipelineResult& result) {
  if (!result.shell) throw std::logic_error("shell_fit_file: the shell stage did not run");
  return shell::to_file(*result.shell);
}

results::YarnFitFile yarn_fit_file(const PipelineResult& result, const std::filesystem::path& targets_file) {
  if (!result.yarn || !result.yarn_problem) throw std::logic_error("yarn_fit_file: the yarn stage did not run");
  results::YarnFitFile f = calibration::to_file(*result.yarn_problem, *result.yarn, result.yarn_settings);
  if (result.shell) f.targets = targets_file.string();
  return f;
}

}  // namespace yarnfit::pipeline
