#include "pipeline/stage_plan.hpp"

#include <algorithm>
#include <stdexcept>

#include "numerics/util/error.hpp"
#include "yarn_fit/fit/problem/generated_pattern.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "pipeline/fitted_tile.hpp"
#include "pipeline/measured_check.hpp"

namespace yarnfit::pipeline {

namespace {

using numerics::Clock;
using numerics::seconds_since;

// The yarn problem of the fabric (no targets yet) from the start file when there is one.
std::optional<yarn::YarnFitProblem> yarn_problem(const db::Fabric& fabric, const PipelineOptions& options,
                                                        db::Problems& problems) {
  auto problem = yarn::make_yarn_fit_problem(fabric, problems);
  if (problem && !options.start.empty())
    yarn::read_start(*problem, options.start, options.yarn.linear_stretch, problems);
  return problem;
}

// A record whose pattern is a knit whose tile must be generated before the yarn fit.
bool tile_to_generate(const db::Fabric& fabric) {
  return fabric.pattern && fabric.pattern->knit && !fabric.pattern->has_tile();
}

// tile: a knit's tile generated (kept in options.tile_cache) and the yarn problem made on it.
// It runs before the shell fit, so that a tile that cannot be made costs no fit.
class TileStage final : public PlanStage {
 public:
  void check(PlanState& state, db::Problems& problems) const override {
    if (!tile_to_generate(state.fabric)) return;
    if (state.options.tile_cache.empty())
      problems.add("", 0, "tile_cache", "the pattern is a knit to generate: say where generated tiles are kept");
    yarn::check_yarn_stiffness(state.fabric, problems);
  }
  bool run(PlanState& state) const override {
    if (!tile_to_generate(state.fabric)) return true;
    db::Problems problems;
    if (yarn::make_generated_pattern(state.fabric, state.options.tile_cache, problems))
      state.result.yarn_problem = yarn_problem(state.fabric, state.options, problems);
    if (problems.empty()) return true;
    refuse(state.result, std::move(problems));
    return false;
  }
};

// shell: the shell fit and its uniform targets. A model that is usable but did not converge
// goes on (the message says why); an unusable one ends the plan.
class ShellStage final : public PlanStage {
 public:
  void check(PlanState& state, db::Problems& problems) const override {
    problems.append(shell_option_problems(state.options));
  }
  bool run(PlanState& state) const override {
    PipelineResult& result = state.result;
    result.shell = shell::fit_shell(state.fabric, state.options.shell);
    result.seconds_shell = seconds_since(state.start);
    if (!result.shell->converged()) result.message = result.shell->failure();
    result.status = result.shell->usable() ? PipelineStatus::ok : PipelineStatus::shell_failed;
    return result.shell->usable();
  }
};

// targets: what the yarn fit fits, the shell stage's in memory (as uniform_targets.csv holds
// them) or, with Stage::yarn, the targets file's (read by the check).
class TargetsStage final : public PlanStage {
 public:
  void check(PlanState& state, db::Problems& problems) const override {
    if (state.options.stages != Stage::yarn) return;
    if (state.options.targets.empty()) problems.add("", 0, "targets", "the yarn stage alone needs a targets file");
    else state.file_targets = db::read_uniform_targets(state.options.targets, problems);
  }
  bool run(PlanState& state) const override {
    auto& problem = *state.result.yarn_problem;
    if (state.result.shell) {
      problem.targets = state.result.shell->targets;
    } else {
      problem.targets = std::move(state.file_targets).value_or(std::vector<db::DirectionTargets>{});
      problem.targets_source = state.options.targets.string();
    }
    return true;
  }
};

// yarn: the yarn fit on the targets. Targets it cannot fit fail it (or, from a file, refuse
// the input: they were the user's).
class YarnStage final : public PlanStage {
 public:
  void check(PlanState& state, db::Problems& problems) const override {
    problems.append(yarn_option_problems(state.options));
    if (!tile_to_generate(state.fabric)) state.result.yarn_problem = yarn_problem(state.fabric, state.options, problems);
  }
  bool run(PlanState& state) const override {
    const auto yarn_start = Clock::now();
    PipelineResult& result = state.result;
    try {
      if (yarn::shape_is_fitted(state.fabric, state.options.yarn, state.options.shape)) {
        result.shape.emplace();
        result.yarn = yarn::fit_yarn_with_shape(*result.yarn_problem, *state.fabric.pattern->knit,
                                                       state.fabric.pattern->tile, state.options.yarn, state.options.shape,
                                                       *result.shape);
        result.fitted_tile = result.shape->tile;
      } else {
        result.yarn = yarn::fit_yarn(*result.yarn_problem, state.options.yarn);
        if (state.fabric.pattern && state.fabric.pattern->has_tile()) result.fitted_tile = state.fabric.pattern->tile;
      }
      if (result.fitted_tile)
        result.fitted_tile_record = describe_fitted_tile(state.fabric, *result.fitted_tile, result.shape.has_value(),
                                                         result.shape && result.shape->held);
      result.status = result.yarn->ok ? PipelineStatus::ok : PipelineStatus::yarn_failed;
      result.message = result.yarn->ok ? std::string() : "yarn fit failed: " + result.yarn->message;
    } catch (const Error& e) {
      // The settings were checked: the targets cannot be fitted.
      if (e.category() != ErrorCategory::input) throw;
      const std::string& file = state.options.targets.string();
      result.status = result.shell ? PipelineStatus::yarn_failed : PipelineStatus::invalid_input;
      result.message = (result.shell ? "the shell stage's uniform targets" : file) + ": " + e.what();
      if (!result.shell) result.problems.add(file, 0, "targets", e.what());
    }
    result.seconds_yarn = seconds_since(yarn_start);
    return result.status == PipelineStatus::ok;
  }
};

// measured: the fitted yarn model homogenised back to a shell law and run through the record's
// own tests (pipeline/measured_check.hpp). What it cannot do is said in its record, never a
// failure of the fit.
class MeasuredStage final : public PlanStage {
 public:
  void check(PlanState&, db::Problems&) const override {}
  bool run(PlanState& state) const override {
    PipelineResult& result = state.result;
    if (!result.yarn || !result.yarn->ok) return true;
    shell::InplaneModel model = state.options.shell.model;
    std::optional<shell::InplaneParams> start;
    if (result.shell) {
      model = result.shell->inplane.model;
      start = result.shell->params.inplane;
    } else if (const auto beside = state.options.targets.parent_path() / "shell_fit.json"; std::filesystem::exists(beside)) {
      // The yarn stage alone: the shell stage's law beside its targets, when it is there.
      try {
        const results::ShellFitFile shell = results::read_shell_fit_file(beside);
        if (const auto m = shell::parse_inplane_model(shell.model)) model = *m;
        std::array<double, shell::k_inplane_param_count> values{};
        bool complete = true;
        for (int k = 0; k < shell::k_inplane_param_count; ++k) {
          const auto it = shell.params.find(shell::k_inplane_param_names[k]);
          if (it != shell.params.end() && it->second) values[static_cast<std::size_t>(k)] = *it->second;
          else if (k < shell::k_first_lockup_param) complete = false;
        }
        if (complete) start = shell::inplane_from_array(values);
      } catch (const std::exception&) {
        // An unreadable shell_fit.json: the law is fitted from the samples alone.
      }
    }
    shell::RecordErrorOptions o;
    o.mesh = state.options.shell.mesh;
    o.full_range = state.options.shell.full_range;
    result.measured = check_against_measurements(state.fabric, *result.yarn, model, start, o);
    return true;
  }
};

}  // namespace

PlanState new_plan_state(const db::Fabric& fabric, const PipelineOptions& options) {
  PlanState state{options, fabric, Clock::now(), std::nullopt, {}};
  PipelineResult& result = state.result;
  result.fabric_id = fabric.id;
  result.fabric_folder = fabric.folder;
  result.yarn_settings = options.yarn;
  result.stages = options.stages;
  return state;
}

void refuse(PipelineResult& result, db::Problems problems) {
  result.status = PipelineStatus::invalid_input;
  result.message = "invalid input: nothing was run";
  result.problems = std::move(problems);
  result.yarn_problem.reset();
}

StagePlan::StagePlan(Stage stages) {
  if (runs_yarn(stages)) m_stages.push_back(std::make_unique<TileStage>());
  if (runs_shell(stages)) m_stages.push_back(std::make_unique<ShellStage>());
  if (runs_yarn(stages)) {
    m_stages.push_back(std::make_unique<TargetsStage>());
    m_stages.push_back(std::make_unique<YarnStage>());
    m_stages.push_back(std::make_unique<MeasuredStage>());
  }
}

void StagePlan::check(PlanState& state, db::Problems& problems) const {
  for (const auto& stage : m_stages) stage->check(state, problems);
  // The exports, written once the fit is (plan.cpp): the shell stage, and what ARCSim reads.
  problems.append(export_option_problems(state.options));
  const auto& formats = state.options.exports;
  if (std::find(formats.begin(), formats.end(), exports::ExportFormat::arcsim) != formats.end() &&
      !state.fabric.areal_density)
    problems.add(state.fabric.folder.string(), 0, "export",
                 "arcsim: the record has no areal_density_gsm, and ARCSim's material needs the areal density");
}

PipelineResult StagePlan::run(PlanState state) const {
  for (const auto& stage : m_stages)
    if (!stage->run(state)) break;
  state.result.seconds_total = seconds_since(state.start);
  return std::move(state.result);
}

}  // namespace yarnfit::pipeline
