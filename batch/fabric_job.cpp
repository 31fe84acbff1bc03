#include "batch/fabric_job.hpp"

#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "calibration/fit/fit_checkpoint.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "pipeline/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "results/shell_fit_file.hpp"

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
  const fs::path out = fabric_output_folder(options.out, spec.fabric_id);
  fs::create_directories(out);
  const db::FabricLoad load = db::load_fabric(spec.folder);
  if (!load.ok()) return {false, load.problems.to_string()};

  pipeline::PipelineOptions o = options.fit;
  o.shell.threads = options.threads_per_job;
  o.yarn.threads = options.threads_per_job;
  o.yarn.checkpoint = swarm_checkpoint_file(out);
  o.tile_cache = generated_tiles_folder(options.out);
  o.yarn.resume = spec.resume && fs::exists(o.yarn.checkpoint);
  if (!o.yarn.resume) calibration::remove_fit_checkpoint(o.yarn.checkpoint);
  if (stage) {
    stage("shell");
    o.shell.progress = [&stage](const reports::Progress& p) { stage("shell " + step_text(p)); };
    o.yarn.progress = [&stage](const reports::Progress& p) { stage(step_text(p)); };
  }
  const pipeline::PipelineResult result = pipeline::run_pipeline(*load.fabric, o);
  if (result.status == pipeline::PipelineStatus::invalid_input) return {false, result.problems.to_string()};
  pipeline::write_pipeline_outputs(result, out);
  if (result.status != pipeline::PipelineStatus::ok) return {false, result.message};
  return {true, ""};
}

double number_at(const json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end()) return std::numeric_limits<double>::quiet_NaN();
  if (it->is_boolean()) return it->get<bool>() ? 1.0 : 0.0;
  if (it->is_number()) return it->get<double>();
  return std::numeric_limits<double>::quiet_NaN();
}

// The yarn stage's row, from yarn_fit.json.
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
    if (c == "converged") v = number_at(j, "ok");
    else if (c == "evaluations") v = number_at(j, "evaluations");
    else if (c == "seconds") v = j.contains("timing_s") && j["timing_s"].is_object() ? number_at(j["timing_s"], "total")
                                                                                    : number_at(j, "timing_s");
    else if (errors.contains(c)) v = number_at(errors, c.c_str());
    else v = number_at(params, c.c_str());
    row.values.push_back(v);
  }
  return row;
}

// The shell stage's row, from shell_fit.json: the ledger's columns take the file's names (its
// errors and parameters); none when the file is missing or unreadable.
std::optional<ResultRow> shell_row(const fs::path& file, const std::string& fabric_id, const std::string& family) {
  if (!fs::exists(file)) return std::nullopt;
  results::ShellFitFile shell;
  try {
    shell = results::read_shell_fit_file(file);
  } catch (const std::runtime_error&) {
    return std::nullopt;
  }
  ResultRow row{fabric_id, "shell", family, {}, results::params_json(shell.params).dump()};
  const std::map<std::string, double> errors = results::named_errors(shell.errors);
  for (const auto& c : result_columns()) {
    double v = std::numeric_limits<double>::quiet_NaN();
    if (c == "converged") v = shell.converged ? 1.0 : 0.0;
    else if (c == "seconds") v = shell.timing_s;
    else if (const auto e = errors.find(c); e != errors.end()) v = e->second;
    else if (const auto p = shell.params.find(c); p != shell.params.end() && p->second) v = *p->second;
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
  if (auto r = shell_row(folder / "shell_fit.json", fabric_id, family)) rows.push_back(std::move(*r));
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
