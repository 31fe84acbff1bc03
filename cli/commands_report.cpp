// yarnfit report DIR… --out REPORT_DIR: the HTML/CSV/JSON report over batch outputs and
// folders of `yarnfit fit` outputs (SPEC §5). Each DIR is one run; the work is the reports
// library's (reports/report.hpp) and, for batch folders, the batch library's ledger reader.
#include <iostream>
#include <memory>

#include "batch/batch_report.hpp"
#include "batch/ledger.hpp"
#include "cli/commands.hpp"
#include "numerics/util/error.hpp"
#include "reports/report.hpp"

namespace yarnfit::cli {

namespace fs = std::filesystem;

namespace {

struct ReportArgs {
  std::vector<std::string> dirs;
  std::string out;
  bool quiet = false;
};

int run_report(const ReportArgs& a) {
  std::vector<reports::RunOutputs> runs;
  bool bad = false;
  for (const auto& dir : a.dirs) {
    try {
      runs.push_back(batch::is_batch_folder(dir) ? batch::read_batch_outputs(dir) : reports::read_fit_folders(dir));
    } catch (const Error& e) {  // not a fit or batch folder, or its ledger cannot be read
      std::cerr << e.what() << "\n";
      bad = true;
    }
  }
  if (bad) return k_exit_invalid_input;
  const reports::ReportData data = reports::make_report_data(std::move(runs));
  for (const auto& p : data.problems) std::cerr << "report: " << p << "\n";
  fs::path index;
  if (!write_files(a.out, [&] { index = reports::write_report(data, a.out); })) return k_exit_internal;
  if (!a.quiet) std::cout << reports::report_written_line(data, index);
  return k_exit_ok;
}

}  // namespace

void add_report_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<ReportArgs>();
  auto* r = app.add_subcommand(
      "report", "HTML report (index.html: summary, errors per family and per fabric, curves, parameters in their "
                "bounds, what accuracy costs across runs) plus fabrics.csv, families.csv and report.json, over batch "
                "folders and folders of `yarnfit fit` outputs; each DIR is one run, a later run's fabric replaces an "
                "earlier's in the tables and all are compared");
  r->add_option("DIR", a->dirs, "Batch folders (with batch.db), `fit` output folders, or folders of them")
      ->required();
  r->add_option("-o,--out", a->out, "Report folder")->required();
  r->add_flag("-q,--quiet", a->quiet, "Print nothing but problems");
  r->callback([a, &exit_code] { exit_code = run_report(*a); });
}

}  // namespace yarnfit::cli
