#include "batch/fabric_job.hpp"

#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "calibration/fit/fit_checkpoint.hpp"
#include "fabrics_db/text_util.hpp"
#include "pipeline/plan.hpp"

namespace yarnfit::batch {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string step_text(const reports::Progress& p) {
  std::string s = p.stage.empty() ? std::string("running") : p.stage;
  if (p.steps > 0) s += " " + std::to_string(p.step) + "/" + std::to_string(p.steps);
  return s;
}

JobOutcome run(const JobSpec& spec, const BatchOptions& options, const StageFn& stage) {
  pipeline::FitPlan plan;
  plan.fabric = spec.folder;
  plan.out = fabric_output_folder(options.out, spec.fabric_id);
  plan.options = options.fit;
  plan.overwrite = true;  // the ledger decides what runs again
  fs::create_directories(plan.out);
  pipeline::PipelineOptions& o = plan.options;
  o.shell.threads = options.threads_per_job;
  o.yarn.threads = options.threads_per_job;
  o.yarn.checkpoint = swarm_checkpoint_file(plan.out);
  o.tile_cache = generated_tiles_folder(options.out);
  o.yarn.resume = spec.resume && fs::exists(o.yarn.checkpoint);
  if (!o.yarn.resume) calibration::remove_fit_checkpoint(o.yarn.checkpoint);
  pipeline::PlanObserver observer;
  if (stage) {
    stage("shell");
    observer = [&stage](const pipeline::StageEvent& e) {
      const std::string step = step_text(e.progress);
      stage(e.stage == pipeline::Stage::shell ? "shell " + step : e.stage == pipeline::Stage::yarn ? step : "report");
    };
  }
  const pipeline::PlanResult result = pipeline::run_plan(plan, observer);
  if (result.fit.status == pipeline::PipelineStatus::invalid_input) return {false, result.fit.problems.to_string()};
  if (!result.write_error.empty()) return {false, result.write_error};
  if (result.fit.status != pipeline::PipelineStatus::ok) return {false, result.fit.message};
  return {true, ""};
}

double number_at(const json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) return std::numeric_limits<double>::quiet_NaN();
  if (it->is_boolean()) return it->get<bool>() ? 1.0 : 0.0;
  if (it->is_number()) return it->get<double>();
  return std::numeric_limits<double>::quiet_NaN();
}

std::optional<ResultRow> row_of(const fs::path& file, const std::string& stage, const std::string& fabric_id,
                                const std::string& family) {
  std::string text, why;
  if (!db::read_text_file(file, text, why)) return std::nullopt;
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return std::nullopt;
  ResultRow row{fabric_id, stage, family, {}, j.value("params", json::object()).dump()};
  const json empty = json::object();
  const json& params = j.contains("params") ? j["params"] : empty;
  const json& errors = j.contains("errors") ? j["errors"] : empty;
  for (const auto& c : result_columns()) {
    double v = std::numeric_limits<double>::quiet_NaN();
    if (c == "converged") v = number_at(j, stage == "shell" ? "converged" : "ok");
    else if (c == "evaluations") v = number_at(j, "evaluations");
    else if (c == "seconds") v = j.contains("timing_s") && j["timing_s"].is_object() ? number_at(j["timing_s"], "total")
                                                                                    : number_at(j, "timing_s");
    else if (errors.contains(c)) v = number_at(errors, c.c_str());
    else v = number_at(params, c.c_str());
    row.values.push_back(v);
  }
  return row;
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
  if (auto r = row_of(folder / "shell_fit.json", "shell", fabric_id, family)) rows.push_back(std::move(*r));
  if (auto r = row_of(folder / "yarn_fit.json", "yarn", fabric_id, family)) rows.push_back(std::move(*r));
  return rows;
}

std::string to_message(const JobSpec& spec) {
  return json{{"fabric_id", spec.fabric_id}, {"family", spec.family}, {"folder", spec.folder.string()},
              {"resume", spec.resume}}
      .dump();
}

JobSpec job_spec_from_message(const std::string& message) {
  const json j = json::parse(message, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::runtime_error("bad job message: " + message);
  return {j.value("fabric_id", ""), j.value("family", ""), j.value("folder", ""), j.value("resume", false)};
}

std::string to_message(const JobOutcome& outcome) { return json{{"ok", outcome.ok}, {"error", outcome.error}}.dump(); }

JobOutcome job_outcome_from_message(const std::string& message) {
  const json j = json::parse(message, nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw std::runtime_error("bad outcome message: " + message);
  return {j.value("ok", false), j.value("error", "")};
}

}  // namespace yarnfit::batch
