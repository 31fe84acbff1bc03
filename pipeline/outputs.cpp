#include "pipeline/outputs.hpp"

#include "fabrics_db/targets/uniform_targets.hpp"
#include "fabrics_db/text_util.hpp"
#include "reports/summaries/fit_summary.hpp"
#include "reports/summaries/shell_summary.hpp"
#include "reports/summaries/yarn_summary.hpp"

namespace yarnfit::pipeline {

namespace fs = std::filesystem;

const std::vector<std::string>& output_files(Stages stages) {
  static const std::vector<std::string> shell{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv"};
  static const std::vector<std::string> yarn{"yarn_fit.json", "yarn_curves.csv", "yarn_summary.txt"};
  static const std::vector<std::string> all{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv",
                                            "yarn_fit.json",  "yarn_curves.csv",     "summary.txt"};
  switch (stages) {
    case Stages::shell: return shell;
    case Stages::yarn: return yarn;
    case Stages::all: break;
  }
  return all;
}

const std::vector<std::string>& report_files() {
  static const std::vector<std::string> files{"report/index.html", "report/fabrics.csv", "report/families.csv",
                                              "report/report.json"};
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

namespace {

// Writes each file whole (db::write_text_file_atomically) and keeps the list.
struct FolderWriter {
  const fs::path& folder;
  PipelineOutputs& out;
  void operator()(const std::string& name, const std::string& text) const {
    db::write_text_file_atomically(folder / name, text);
    out.files.push_back(name);
  }
};

std::string listed(const std::vector<std::string>& files) {
  std::string s;
  for (const auto& f : files) s += (s.empty() ? "" : ", ") + f;
  return s;
}

// shell_fit.json, uniform_targets.csv and, for a usable model, shell_curves.csv; returns the
// JSON.
nlohmann::json write_shell_stage(const shell::ShellFitResult& shell, const FolderWriter& write) {
  nlohmann::json j = shell::to_json(shell);
  write("shell_fit.json", j.dump(2) + "\n");
  db::write_uniform_targets_csv(shell.targets, write.folder / "uniform_targets.csv");
  write.out.files.push_back("uniform_targets.csv");
  write.out.text = reports::shell_fit_report(j);
  if (shell.usable()) write("shell_curves.csv", reports::shell_curves_csv(j));
  return j;
}

}  // namespace

PipelineOutputs write_outputs(const PipelineResult& result, const fs::path& folder) {
  PipelineOutputs out;
  if (!result.shell && !result.yarn) return out;
  fs::create_directories(folder);
  const FolderWriter write{folder, out};
  const auto results_line = [&] { return "results in " + folder.string() + ": " + listed(out.files) + "\n"; };
  const nlohmann::json shell = result.shell ? write_shell_stage(*result.shell, write) : nlohmann::json();
  if (!result.yarn) {
    out.text += results_line();
    return out;
  }
  const nlohmann::json yarn = yarn_fit_json(result, folder / "uniform_targets.csv");
  if (result.shell) {
    write("yarn_fit.json", yarn.dump(2) + "\n");
    write("yarn_curves.csv", reports::yarn_curves_csv(yarn));
    out.summary = reports::fit_summary(result.fabric_id, result.fabric_folder.string(), shell, yarn,
                                       {result.seconds_shell, result.seconds_yarn, result.seconds_total});
    write("summary.txt", out.summary);
    out.text += "\n" + out.summary;
  } else {
    out.summary = write_yarn_outputs(yarn, folder);
    out.files = output_files(Stages::yarn);
    out.text = "yarn fit of " + result.fabric_id + "\n" + out.summary;
  }
  out.text += results_line();
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
