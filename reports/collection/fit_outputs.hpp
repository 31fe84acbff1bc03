#pragma once
// What a report reads: the output folders of `yarnfit fit` (shell_fit.json, yarn_fit.json),
// one run at a time. A run is one batch output (its ledger says which fabrics failed and why;
// batch/batch_report.hpp reads it) or a folder of `fit` outputs. The files are read as the
// result types (results/), so a report needs none of the fit types and no JSON key.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "results/shell_fit_file.hpp"
#include "results/yarn_fit_file.hpp"

namespace yarnfit::reports {

struct FabricOutputs {
  std::string id;
  std::string family;
  std::filesystem::path folder;
  // done, failed, running or queued (a batch's ledger), or from the files: failed when a stage
  // that ran did not converge, done otherwise.
  std::string status = "done";
  std::string error;    // why it failed
  std::optional<results::ShellFitFile> shell;  // shell_fit.json, when there is a readable one
  std::optional<results::YarnFitFile> yarn;    // yarn_fit.json, when there is a readable one
  std::vector<std::filesystem::path> exports;  // the files under exports/ (`--export`), by name
  std::optional<db::PeriodicTile> tile;  // tile.pyp: the tile the yarn model was fitted on, when readable
};

struct RunOutputs {
  std::string label;                   // how the report names the run (the folder's name)
  std::filesystem::path source;        // the folder given
  std::vector<FabricOutputs> fabrics;  // in id order
  std::vector<std::string> problems;   // files that could not be read (the run goes on)
};

// One fabric's folder of `fit` outputs; `problems` gets one line per unreadable file (naming
// the field that could not be read). The id and family come from the files, else the folder's
// name and "".
FabricOutputs read_fit_outputs(const std::filesystem::path& folder, std::vector<std::string>& problems);

// A folder of `fit` outputs, or a folder whose sub-folders are (each holding shell_fit.json).
// Throws an input Error when it is neither.
RunOutputs read_fit_folders(const std::filesystem::path& dir);

}  // namespace yarnfit::reports
