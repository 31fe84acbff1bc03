#pragma once
// The output folders of the fit commands (SPEC §5), each file written atomically
// (db::write_text_file_atomically): a reader never sees half a file, and an interrupted run
// leaves whole files or none.
//
//   `yarnfit shell fit` shell_fit.json, uniform_targets.csv
//   `yarnfit fit`       shell_fit.json, uniform_targets.csv, shell_curves.csv, yarn_fit.json,
//                       yarn_curves.csv, summary.txt
//   `yarnfit yarn fit`  yarn_fit.json, yarn_curves.csv, yarn_summary.txt

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "pipeline/pipeline.hpp"

namespace yarnfit::pipeline {

// The files write_pipeline_outputs writes, and those of write_yarn_outputs.
[[nodiscard]] const std::vector<std::string>& pipeline_output_files();
[[nodiscard]] const std::vector<std::string>& yarn_output_files();

// Problems with writing `files` into `folder`: the folder is a file, or (unless `overwrite`)
// each of the files that exists. Checked before any work, so a run never ends unable to
// write, nor replaces results it was not asked to.
[[nodiscard]] db::Problems output_problems(const std::filesystem::path& folder, const std::vector<std::string>& files,
                                           bool overwrite);

// A shell fit's files (SPEC §5 `yarnfit shell fit`): shell_fit.json and uniform_targets.csv,
// in `folder` (created if needed). Returns shell_fit.json's content. Throws
// std::runtime_error naming a file it cannot write.
results::ShellFitFile write_shell_outputs(const shell::ShellFitResult& result, const std::filesystem::path& folder);

// What write_pipeline_outputs wrote.
struct PipelineOutputs {
  std::vector<std::string> files;  // names written into the folder, in order
  std::string summary;             // summary.txt (empty when the yarn stage did not run)
};

// Writes the folder (created if needed) from a result of run_pipeline: after the shell stage
// shell_fit.json and uniform_targets.csv; when the shell fit converged also shell_curves.csv;
// when the yarn stage ran yarn_fit.json, yarn_curves.csv and summary.txt. Nothing for an
// invalid input. Throws std::runtime_error naming the file that could not be written.
PipelineOutputs write_pipeline_outputs(const PipelineResult& result, const std::filesystem::path& folder);

// A yarn fit's folder (created if needed): yarn_fit.json, yarn_curves.csv and
// yarn_summary.txt (reports::yarn_summary_file, naming yarn_fit.json's fabric and targets).
// Returns the yarn summary's text. Throws std::runtime_error naming a file it cannot write.
std::string write_yarn_outputs(const nlohmann::json& yarn_fit, const std::filesystem::path& folder);

}  // namespace yarnfit::pipeline
