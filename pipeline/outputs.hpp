#pragma once
// The output folders of the fit commands (SPEC §5), each file written atomically
// (db::write_text_file_atomically): a reader never sees half a file, and an interrupted run
// leaves whole files or none.
//
//   `yarnfit shell fit` shell_fit.json, uniform_targets.csv, shell_curves.csv
//   `yarnfit fit`       shell_fit.json, uniform_targets.csv, shell_curves.csv, yarn_fit.json,
//                       yarn_curves.csv, summary.txt (and report/)
//   `yarnfit yarn fit`  yarn_fit.json, yarn_curves.csv, yarn_summary.txt

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "pipeline/pipeline.hpp"

namespace yarnfit::pipeline {

// The files a run of `stages` writes (shell: shell_fit.json, uniform_targets.csv,
// shell_curves.csv; yarn: yarn_fit.json, yarn_curves.csv, yarn_summary.txt; all: the shell
// stage's, then yarn_fit.json, yarn_curves.csv and summary.txt), and those of the one-fabric
// report under the folder.
[[nodiscard]] const std::vector<std::string>& output_files(Stage stages);
[[nodiscard]] const std::vector<std::string>& report_files();

// Problems with writing `files` into `folder`: the folder is a file, or (unless `overwrite`)
// each of the files that exists. Checked before any work, so a run never ends unable to
// write, nor replaces results it was not asked to.
[[nodiscard]] db::Problems output_problems(const std::filesystem::path& folder, const std::vector<std::string>& files,
                                           bool overwrite);

// Writes the folder (created if needed) from a fit's result (run_plan), for the stages that
// ran: after the shell stage shell_fit.json and uniform_targets.csv, and when its model is
// usable shell_curves.csv; after the yarn stage yarn_fit.json, yarn_curves.csv and
// summary.txt (yarn_summary.txt when it ran alone). Nothing for an invalid input. Throws
// an Error naming the file that could not be written.
PipelineOutputs write_outputs(const PipelineResult& result, const std::filesystem::path& folder);

// A yarn fit's folder (created if needed), as write_outputs writes it after the yarn stage alone:
// yarn_fit.json, yarn_curves.csv and yarn_summary.txt (reports::yarn_summary_file, naming the
// fabric and the targets). Returns the yarn summary's text. Throws an Error naming a
// file it cannot write.
std::string write_yarn_outputs(const results::YarnFitFile& yarn_fit, const std::filesystem::path& folder);

}  // namespace yarnfit::pipeline
