#include "pipeline/pipeline.hpp"

#include <chrono>
#include <stdexcept>

#include "calibration/problem/generated_pattern.hpp"
#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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

PipelineResult run(const db::Fabric& given, const PipelineOptions& options, Clock::time_point start) {
  PipelineResult result;
  result.fabric_id = given.id;
  result.fabric_folder = given.folder;
  result.yarn_settings = options.yarn;
  result.problems = options.problems();
  db::Fabric fabric = given;
  if (options.stages == Stages::all && tile_to_generate(fabric)) {
    check_generated_pattern(fabric, options, result.problems);
    if (result.problems.empty()) calibration::make_generated_pattern(fabric, options.tile_cache, result.problems);
  }
  if (options.stages == Stages::all && !tile_to_generate(fabric))
    result.yarn_problem = yarn_problem(fabric, options, result.problems);
  if (!result.problems.empty()) {
    result.status = PipelineStatus::invalid_input;
    result.message = "invalid input: nothing was run";
    result.yarn_problem.reset();
    return result;
  }

  // Stage 1: the shell fit and its uniform targets.
  result.shell = shell::fit_shell(fabric, options.shell);
  result.seconds_shell = seconds_since(start);
  if (!result.shell->usable()) {
    result.status = PipelineStatus::shell_failed;
    result.message = result.shell->failure();
    result.seconds_total = seconds_since(start);
    return result;
  }
  if (options.stages == Stages::shell) {
    result.status = PipelineStatus::ok;
    result.seconds_total = seconds_since(start);
    return result;
  }

  // Stage 2: the yarn fit on those targets, handed over in memory (as the file holds them).
  const auto yarn_start = Clock::now();
  result.yarn_problem->targets = result.shell->targets;
  try {
    result.yarn = calibration::fit_yarn(*result.yarn_problem, options.yarn);
  } catch (const std::invalid_argument& e) {
    // The settings were checked above: the shell stage's targets cannot be fitted.
    result.status = PipelineStatus::yarn_failed;
    result.message = std::string("the shell stage's uniform targets: ") + e.what();
    result.seconds_yarn = seconds_since(yarn_start);
    result.seconds_total = seconds_since(start);
    return result;
  }
  result.seconds_yarn = seconds_since(yarn_start);
  result.seconds_total = seconds_since(start);
  result.status = result.yarn->ok ? PipelineStatus::ok : PipelineStatus::yarn_failed;
  if (!result.yarn->ok) result.message = "yarn fit failed: " + result.yarn->message;
  return result;
}

}  // namespace

const char* to_string(Stages stages) { return stages == Stages::shell ? "shell" : "all"; }

std::optional<Stages> stages_from_string(std::string_view name) {
  if (name == "shell") return Stages::shell;
  if (name == "all") return Stages::all;
  return std::nullopt;
}

db::Problems PipelineOptions::problems() const {
  db::Problems out;
  add_prefixed(out, shell.problems(), "shell.");
  if (stages == Stages::shell) return out;
  calibration::YarnFitSettings checked = yarn;
  if (!start.empty()) checked.swarm = false;  // a start skips the swarm: its settings do not matter
  add_prefixed(out, checked.problems(), "yarn.");
  return out;
}

db::Problems pipeline_problems(const db::Fabric& fabric, const PipelineOptions& options) {
  db::Problems problems = options.problems();
  if (options.stages != Stages::all) return problems;
  if (tile_to_generate(fabric)) check_generated_pattern(fabric, options, problems);
  else (void)yarn_problem(fabric, options, problems);
  return problems;
}

PipelineResult run_pipeline(const db::Fabric& fabric, const PipelineOptions& options) {
  return run(fabric, options, Clock::now());
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
  return run(*load.fabric, options, start);
}

results::ShellFitFile shell_fit_file(const PipelineResult& result) {
  if (!result.shell) throw std::logic_error("shell_fit_file: the shell stage did not run");
  return shell::to_file(*result.shell);
}

nlohmann::json yarn_fit_json(const PipelineResult& result, const std::filesystem::path& targets_file) {
  if (!result.yarn || !result.yarn_problem) throw std::logic_error("yarn_fit_json: the yarn stage did not run");
  nlohmann::json j = calibration::to_json(*result.yarn_problem, *result.yarn, result.yarn_settings);
  j["targets"] = targets_file.string();
  return j;
}

}  // namespace yarnfit::pipeline
