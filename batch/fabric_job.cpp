#include "batch/fabric_job.hpp"

#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "numerics/util/error.hpp"
#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "fabrics_db/text_util.hpp"
#include "pipeline/plan.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "results/read_if_present.hpp"
#include "results/shell_fit_file.hpp"
#include "results/yarn_fit_file.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string step_text(const numerics::Progress& p) {
  std::string s = p.stage.empty() ? std::string("running") : p.stage;
  if (p.steps > 0) s += " " + std::to_string(p.step) + "/" + std::to_string(p.steps);
  return s;
}

JobOutcome run(const JobSpec& spec, const BatchOptions& options, const StageFn& stage) {
  pipeline::FitPlan plan;
  plan.fabric = spec.folder;
  plan.out = fabric_output_folder(options.out, spec.fabric_id);
  plan.options = options.fit;
  plan.report = spec.report;
  if (spec.fit) {
    plan.options = *spec.fit;
  } else if (options.fabric_of) {
    if (const std::optional<BatchFabric> own = options.fabric_of(spec.fabric_id)) {
      plan.options = own->fit;
      plan.report = own->report;
    }
  }
  plan.overwrite = true;  // the ledger decides what runs again
  fs::create_directories(plan.out);
  pipeline::PipelineOptions& o = plan.options;
  o.shell.threads = options.threads_per_job;
  o.yarn.threads = options.threads_per_job;
  o.yarn.checkpoint = swarm_checkpoint_file(plan.out);
  o.tile_cache = generated_tiles_folder(options.out);
  o.yarn.resume = spec.resume && fs::exists(o.yarn.checkpoint);
  if (!o.yarn.resume) yarn::remove_fit_checkpoint(o.yarn.checkpoint);
  pipeline::PlanObserver observer;
  if (stage) {
    stage("shell");
    observer = [&stage](const pipeline::StageEvent& e) {
      const std::string step = step_text(e.progress);
      stage(e.stage == pipeline::Stage::shell ? "shell " + step
            : e.stage == pipeline::Stage::yarn ? step
                                               : std::string(pipeline::to_string(e.stage)));
    };
  }
  const pipeline::PipelineResult result = pipeline::run_plan(plan, observer);
  if (result.status == pipeline::PipelineStatus::invalid_input) return {false, result.problems.to_string()};
  if (!result.write_error.empty()) return {false, result.write_error};
  if (result.status != pipeline::PipelineStatus::ok) return {false, result.message};
  return {true, ""};
}

using numerics::k_nan;

// What a stage's row holds; the ledger's columns take the result file's names (its errors and
// parameters).
struct StageFigures {
  std::string params_json;
  double converged = k_nan;  // 1 or 0
  double evaluations = k_nan;
  double seconds = k_nan;
  std::map<std::string, double> errors;
  std::map<std::string, double> params;  // fitted values only
};

ResultRow ledger_row(const std::string& fabric_id, const std::string& stage, const std::string& family,
                     const StageFigures& f) {
  ResultRow row{fabric_id, stage, family, {}, f.params_json};
  for (const auto& c : result_columns()) {
    double v = k_nan;
    if (c == "converged") v = f.converged;
    else if (c == "evaluations") v = f.evaluations;
    else if (c == "seconds") v = f.seconds;
    else if (const auto e = f.errors.find(c); e != f.errors.end()) v = e->second;
    else if (const auto p = f.params.find(c); p != f.params.end()) v = p->second;
    row.values.push_back(v);
  }
  return row;
}

// A stage's row; none when its file is missing or unreadable (the row is left out).
std::optional<ResultRow> shell_row(const fs::path& file, const std::string& fabric_id, const std::string& family) {
  const auto shell = results::read_if_present<results::ShellFitFile>(file, results::read_shell_fit_file);
  if (!shell) return std::nullopt;
  StageFigures f{results::params_json(shell->params).dump(), shell->converged ? 1.0 : 0.0, k_nan, shell->timing_s,
                 results::named_errors(shell->errors), {}};
  for (const auto& [name, v] : shell->params)
    if (v) f.params[name] = *v;
  return ledger_row(fabric_id, "shell", family, f);
}

std::optional<ResultRow> yarn_row(const fs::path& file, const std::string& fabric_id, const std::string& family) {
  const auto yarn = results::read_if_present<results::YarnFitFile>(file, results::read_yarn_fit_file);
  if (!yarn) return std::nullopt;
  const StageFigures f{json(yarn->params).dump(), yarn->ok ? 1.0 : 0.0, static_cast<double>(yarn->evaluations),
                       yarn->timing_s.total, results::named_errors(yarn->errors), yarn->params};
  return ledger_row(fabric_id, "yarn", family, f);
}

}  // namespace

bool StageThrottle::pass(const std::string& stage) {
  const auto now = std::chrono::steady_clock::now();
  const bool new_name = stage.substr(0, stage.find(' ')) != m_last.substr(0, m_last.find(' '));
  if (stage == m_last || (!new_name && now - m_last_time < std::chrono::milliseconds(500))) return false;
  m_last = stage;
  m_last_time = now;
  return true;
}

JobOutcome run_fabric_job(const JobSpec& spec, const BatchOptions& options, const StageFn& stage) {
  try {
    return run(spec, options, stage);
  } catch (const std::exception& e) {
    return {false, e.what()};
  } catch (...) {
    return {false, "unknown exception"};
  }
}

std::vector<ResultRow> read_result_rows(const fs::path& folder, const std::string& fabric_id,
                                        const std::string& family) {
  std::vector<ResultRow> rows;
  if (auto r = shell_row(folder / "shell_fit.json", fabric_id, family)) rows.push_back(std::move(*r));
  if (auto r = yarn_row(folder / "yarn_fit.json", fabric_id, family)) rows.push_back(std::move(*r));
  return rows;
}

std::string to_message(const JobSpec& spec) {
  return json{{"fabric_id", spec.fabric_id}, {"family", spec.family}, {"folder", spec.folder.string()},
              {"resume", spec.resume}}
      .dump();
}

JobSpec job_spec_from_message(const std::string& message) {
  const json j = json::parse(message, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw Error(ErrorCategory::system, "bad job message: " + message);
  return {j.value("fabric_id", ""), j.value("family", ""), j.value("folder", ""), j.value("resume", false), std::nullopt,
          false};
}

std::string to_message(const JobOutcome& outcome) { return json{{"ok", outcome.ok}, {"error", outcome.error}}.dump(); }

JobOutcome job_outcome_from_message(const std::string& message) {
  const json j = json::parse(message, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw Error(ErrorCategory::system, "bad outcome message: " + message);
  return {j.value("ok", false), j.value("error", "")};
}

}  // namespace yarnfit::batch
