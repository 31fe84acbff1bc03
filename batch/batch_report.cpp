#include "batch/batch_report.hpp"

#include <algorithm>

#include "batch/batch_options.hpp"
#include "batch/ledger.hpp"
#include "reports/report.hpp"

namespace yarnfit::batch {

namespace fs = std::filesystem;

bool is_batch_folder(const fs::path& dir) { return fs::exists(ledger_file(dir)); }

reports::RunOutputs read_batch_outputs(const fs::path& dir) {
  const Ledger ledger = Ledger::open_read_only(ledger_file(dir));
  reports::RunOutputs run;
  run.source = dir;
  run.label = fs::weakly_canonical(dir).filename().string();
  for (const JobRow& job : ledger.jobs()) {
    const fs::path folder = fabric_output_folder(dir, job.fabric_id);
    reports::FabricOutputs f;
    if (fs::is_directory(folder)) f = reports::read_fit_outputs(folder, run.problems);
    f.folder = folder;
    f.id = job.fabric_id;
    f.family = job.family;
    f.status = job.status;
    f.error = job.error;
    // A job that is not done may have left the files of a stage that finished (the shell fit
    // before the yarn stage failed): they are shown as they are, beside the ledger's reason.
    run.fabrics.push_back(std::move(f));
  }
  std::sort(run.fabrics.begin(), run.fabrics.end(),
            [](const reports::FabricOutputs& a, const reports::FabricOutputs& b) { return a.id < b.id; });
  return run;
}

fs::path write_batch_report(const fs::path& dir) {
  std::vector<reports::RunOutputs> runs;
  runs.push_back(read_batch_outputs(dir));
  return reports::write_report(reports::make_report_data(std::move(runs)), dir / "report");
}

}  // namespace yarnfit::batch
