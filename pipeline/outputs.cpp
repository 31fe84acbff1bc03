#include "pipeline/outputs.hpp"

#include "fabrics_db/targets/uniform_targets.hpp"
#include "fabrics_db/text_util.hpp"
#include "reports/summaries/fit_summary.hpp"
#include "reports/summaries/shell_summary.hpp"
#include "reports/summaries/yarn_summary.hpp"

namespace yarnfit::pipeline {

namespace fs = std::filesystem;

const std::vector<std::string>& pipeline_output_files() {
  static const std::vector<std::string> files{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv",
                                              "yarn_fit.json",  "yarn_curves.csv",     "summary.txt"};
  return files;
}

const std::vector<std::string>& yarn_output_files() {
  static const std::vector<std::string> files{"yarn_fit.json", "yarn_curves.csv", "yarn_summary.txt"};
  return files;
}

db::Problems output_problems(const fs::path& folder, const std::vector<std::string>& files, bool overwrite) {
  // The path itself is what the problem is about: it goes where an option's name would
  // ("DIR/yarn_fit.json: exists (use --force to replace it)").
  db::Problems out;
  if (fs::exists(folder) && !fs::is_directory(folder)) {
    out.add("", 0, folder.string(), "exists and is not a folder");
    return out;
  }
  if (overwrite) return out;
  for (const auto& f : files) {
    const fs::path p = folder / f;
    if (fs::exists(p)) out.add("", 0, p.string(), "exists (use --force to replace it)");
  }
  return out;
}

results::ShellFitFile write_shell_outputs(const shell::ShellFitResult& result, const fs::path& folder) {
  fs::create_directories(folder);
  results::ShellFitFile shell = shell::to_file(result);
  db::write_text_file_atomically(folder / "shell_fit.json", results::to_json(shell).dump(2) + "\n");
  db::write_uniform_targets_csv(result.targets, folder / "uniform_targets.csv");
  return shell;
}

PipelineOutputs write_pipeline_outputs(const PipelineResult& result, const fs::path& folder) {
  PipelineOutputs out;
  if (!result.shell) return out;
  const auto write = [&](const std::string& name, const std::string& text) {
    db::write_text_file_atomically(folder / name, text);
    out.files.push_back(name);
  };
  const results::ShellFitFile shell = write_shell_outputs(*result.shell, folder);
  out.files = {"shell_fit.json", "uniform_targets.csv"};
  if (result.status == PipelineStatus::shell_failed) return out;
  write("shell_curves.csv", reports::shell_curves_csv(shell));
  if (!result.yarn) return out;
  const nlohmann::json yarn = yarn_fit_json(result, folder / "uniform_targets.csv");
  write("yarn_fit.json", yarn.dump(2) + "\n");
  write("yarn_curves.csv", reports::yarn_curves_csv(yarn));
  out.summary = reports::fit_summary(result.fabric_id, result.fabric_folder.string(), shell, yarn,
                                     {result.seconds_shell, result.seconds_yarn, result.seconds_total});
  write("summary.txt", out.summary);
  return out;
}

std::string write_yarn_outputs(const nlohmann::json& yarn_fit, const fs::path& folder) {
  fs::create_directories(folder);
  db::write_text_file_atomically(folder / "yarn_fit.json", yarn_fit.dump(2) + "\n");
  db::write_text_file_atomically(folder / "yarn_curves.csv", reports::yarn_curves_csv(yarn_fit));
  const std::string summary = reports::yarn_summary(yarn_fit);
  db::write_text_file_atomically(folder / "yarn_summary.txt",
                                 reports::yarn_summary_file(yarn_fit.value("fabric", std::string()),
                                                            yarn_fit.value("targets", std::string()), yarn_fit));
  return summary;
}

}  // namespace yarnfit::pipeline
