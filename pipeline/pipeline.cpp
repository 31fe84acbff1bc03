#include "pipeline/pipeline.hpp"

#include <cmath>
#include <stdexcept>

#include "pipeline/stage_plan.hpp"

namespace yarnfit::pipeline {

namespace {

void add_prefixed(db::Problems& out, const db::Problems& in, const std::string& prefix) {
  for (const auto& p : in.items()) out.add(p.file, p.line, prefix + p.field, p.message);
}

}  // namespace

const char* to_string(Stage stage) {
  switch (stage) {
    case Stage::all: return "all";
    case Stage::tile: return "tile";
    case Stage::shell: return "shell";
    case Stage::targets: return "targets";
    case Stage::yarn: return "yarn";
    case Stage::exports: return "export";
    case Stage::report: return "report";
  }
  return "?";
}

bool runs_shell(Stage stages) { return stages == Stage::all || stages == Stage::shell; }
bool runs_yarn(Stage stages) { return stages == Stage::all || stages == Stage::yarn; }

std::optional<Stage> stages_from_string(std::string_view name) {
  for (const Stage s : {Stage::all, Stage::shell, Stage::yarn})
    if (name == to_string(s)) return s;
  return std::nullopt;
}

db::Problems shell_option_problems(const PipelineOptions& options) {
  db::Problems out;
  add_prefixed(out, options.shell.problems(), "shell.");
  return out;
}

db::Problems yarn_option_problems(const PipelineOptions& options) {
  yarn::YarnFitSettings checked = options.yarn;
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
  db::Problems out;
  if (!stages_from_string(to_string(stages)))
    out.add("", 0, "stages", std::string("a fit runs all its stages, or the shell or the yarn fit alone, not '") +
                                 to_string(stages) + "'");
  out.append(shell_option_problems(*this));
  if (runs_yarn(stages)) out.append(yarn_option_problems(*this));
  out.append(export_option_problems(*this));
  return out;
}

results::ShellFitFile shell_fit_file(const PipelineResult& result) {
  if (!result.shell) throw std::logic_error("shell_fit_file: the shell stage did not run");
  return shell::to_file(*result.shell);
}

results::YarnFitFile yarn_fit_file(const PipelineResult& result, const std::filesystem::path& targets_file) {
  if (!result.yarn || !result.yarn_problem) throw std::logic_error("yarn_fit_file: the yarn stage did not run");
  results::YarnFitFile f = yarn::to_file(*result.yarn_problem, *result.yarn, result.yarn_settings);
  if (result.shell) f.targets = targets_file.string();
  f.measured = result.measured;
  f.tile = result.fitted_tile_record;
  if (result.shape) {
    const yarn::ShapeFit& s = *result.shape;
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
