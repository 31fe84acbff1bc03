#pragma once
// The summary files of the fit commands, from their results: summary.txt of the whole
// pipeline (`yarnfit fit`) and yarn_summary.txt of a yarn fit alone (`yarnfit yarn fit`).

#include <string>

#include "results/shell_fit_file.hpp"
#include "results/yarn_fit_file.hpp"

namespace yarnfit::reports {

// Wall time of the pipeline's stages [s].
struct StageSeconds {
  double shell = 0.0;  // from the start (reading the record) to the shell stage's end
  double yarn = 0.0;
  double total = 0.0;
};

// summary.txt: the fabric (its id and the folder it was read from), the shell summary, the
// yarn summary and the time per stage.
[[nodiscard]] std::string fit_summary(const std::string& fabric_id, const std::string& fabric_folder,
                                      const results::ShellFitFile& shell_fit, const results::YarnFitFile& yarn_fit,
                                      const StageSeconds& seconds);

// yarn_summary.txt: the fabric, where the targets came from, and the yarn summary.
[[nodiscard]] std::string yarn_summary_file(const std::string& fabric_id, const std::string& targets,
                                            const results::YarnFitFile& yarn_fit);

}  // namespace yarnfit::reports
