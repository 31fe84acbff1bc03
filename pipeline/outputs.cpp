#include "pipeline/outputs.hpp"

#include <optional>

#include "fabrics_db/targets/uniform_targets.hpp"
#include "fabrics_db/text_util.hpp"
#include "reports/summaries/fit_summary.hpp"
#include "reports/summaries/shell_summary.hpp"
#include "reports/summaries/yarn_summary.hpp"

namespace yarnfit::pipeline {

namespace fs = std::filesystem;

const std::vector<std::string>& output_files(Stage stages) {
  static const std::vector<std::string> shell{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv"};
  static const std::vector<std::string> yarn{"yarn_fit.json", "yarn_curves.csv", "yarn_summary.txt", "tile.pyp"};
  static const std::vector<std::string> all{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv", "yarn_fit.json",
                                            "yarn_curves.csv", "summary.txt",         "tile.pyp"};
  switch (stages) {
    case Stage::shell: return shell;
    case Stage::yarn: return yarn;
    default: break;
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

// shell_fit.json, uniform_targets.csv and, for a usable model, shell_curves.csv; returns what
// shell_fit.json holds.
results::ShellFitFile write_shell_stage(const shell::ShellFitResult& shell, const FolderWriter& write) {
  const results::ShellFitFile j = shell::to_file(shell);
  write("shell_fit.json", results::to_json(j).dump(2) + "\n");
  db::write_uniform_targets_csv(shell.targets, write.folder / "uniform_targets.csv");
  write.out.files.push_back("uniform_targets.csv");
  write.out.text = reports::shell_fit_report(j);
  if (shell.usable()) write("shell_curves.csv", reports::shell_curves_csv(j));
  return j;
}

// yarn_fit.json and yarn_curves.csv.
void write_yarn_files(const results::YarnFitFile& yarn, const FolderWriter& write) {
  write("yarn_fit.json", results::to_json(yarn).dump(2) + "\n");
  write("yarn_curves.csv", reports::yarn_curves_csv(yarn));
}

// The yarn stage alone: its two files and yarn_summary.txt (naming the fabric and the targets);
// returns the yarn summary.
std::string write_yarn_stage(const results::YarnFitFile& yarn, const FolderWriter& write) {
  write_yarn_files(yarn, write);
  const std::string summary = reports::yarn_summary(yarn);
  write("yarn_summary.txt", reports::yarn_summary_file(yarn.fabric, yarn.targets, yarn));
  return summary;
}

}  // namespace

PipelineOutputs write_outputs(const PipelineResult& result, const fs::path& folder) {
  PipelineOutputs out;
  if (!result.shell && !result.yarn) return out;
  fs::create_directories(folder);
  const FolderWriter write{folder, out};
  const auto results_line = [&] { return "results in " + folder.string() + ": " + listed(out.files) + "\n"; };
  const std::optional<results::ShellFitFile> shell =
      result.shell ? std::optional(write_shell_stage(*result.shell, write)) : std::nullopt;
  if (!result.yarn) {
    out.text += results_line();
    return out;
  }
  const results::YarnFitFile yarn = yarn_fit_file(result, folder / "uniform_targets.csv");
  if (!shell) {
    out.summary = write_yarn_stage(yarn, write);
    out.text = "yarn fit of " + result.fabric_id + "\n" + out.summary;
  } else {
    write_yarn_files(yarn, write);
    out.summary = reports::fit_summary(result.fabric_id, result.fabric_folder.string(), *shell, yarn,
                                       {result.seconds_shell, result.seconds_yarn, result.seconds_total});
    write("summary.txt", out.summary);
    out.text += "\n" + out.summary;
  }
  // The tile the yarn model was fitted on, beside it (a generated or shape-fitted one exists
  // nowhere else the user looks).
  if (result.fitted_tile) write("tile.pyp", db::format_pyp(*result.fitted_tile));
  out.text += results_line();
  return out;
}

std::string write_yarn_outputs(const results::YarnFitFile& yarn_fit, const fs::path& folder) {
  fs::create_directories(folder);
  PipelineOutputs out;
  return write_yarn_stage(yarn_fit, FolderWriter{folder, out});
}

}  // namespace yarnfit::pipeline
