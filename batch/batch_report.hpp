#pragma once
// A batch folder as a run of the report (reports/report.hpp): every fabric of its ledger with
// the status and the error the ledger holds (so failed and unfinished fabrics are shown with
// their reasons even when they left no files), and the fit outputs in DIR/fabrics/<id>/.

#include <filesystem>

#include "reports/collection/fit_outputs.hpp"

namespace yarnfit::batch {

// True when `dir` holds a batch ledger (DIR/batch.db).
[[nodiscard]] bool is_batch_folder(const std::filesystem::path& dir);

// Throws an Error when the ledger cannot be read.
reports::RunOutputs read_batch_outputs(const std::filesystem::path& dir);

// The report of one batch folder written to DIR/report/ (what `batch` does when it ends);
// returns the path of its index.html.
std::filesystem::path write_batch_report(const std::filesystem::path& dir);

}  // namespace yarnfit::batch
