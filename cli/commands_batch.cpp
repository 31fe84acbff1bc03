// yarnfit batch DB --out DIR …: every fabric of a database through the pipeline (SPEC §5,
// §5a), and `yarnfit batch status DIR`. The work, the ledger and the resumption are the
// batch library's (batch/batch.hpp); this file parses the options, shows the progress line on
// a terminal and prints the summary.
//
// Exit codes: 0 every selected fabric done; 1 some failed (each listed on stderr with its
// reason), the batch was interrupted, or DIR cannot be used (io, system); 2 invalid arguments,
// or DIR in use by another batch (the error's category, cli::exit_code_of).
#include <unistd.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "batch/batch.hpp"
#include "batch/batch_report.hpp"
#include "cli/batch_progress.hpp"
#include "cli/commands.hpp"
#include "cli/fit_args.hpp"
#include "cli/option_names.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;

// The options bind straight to the batch library's (`batch`), and the fit's to the request
// every front end gives the pipeline (`fit`).
struct BatchArgs {
  batch::BatchOptions batch;
  pipeline::FitRequest fit;
  bool quiet = false, no_report = false, mpi = false;
};

int run_batch_command(const BatchArgs& a) {
  db::Problems problems;
  batch::BatchOptions o = a.batch;
  o.fit = pipeline::pipeline_options(a.fit, problems);
  problems.append(o.problems());
  if (!problems.empty()) {
    std::cerr << as_options(problems).to_string();
    return k_exit_invalid_input;
  }
  const bool show = !a.quiet && ::isatty(STDERR_FILENO);
  if (show)
    o.progress = [](const batch::BatchProgress& p) { std::cerr << "\r\033[K" << batch_progress_line(p) << std::flush; };
  batch::BatchSummary s;
  try {
    s = a.mpi ? batch::run_batch_mpi(o) : batch::run_batch(o);
  } catch (const Error& e) {  // nothing ran: the options, the folder in use or unusable, no MPI
    if (show) std::cerr << "\n";
    std::cerr << e.what() << (std::string(e.what()).ends_with("\n") ? "" : "\n");
    return exit_code_of(e);
  }
  if (!s.coordinator) return k_exit_ok;  // an MPI worker: rank 0 reports
  if (show) std::cerr << "\n";
  if (!a.quiet) {
    std::cout << "batch " << o.database.string() << " -> " << o.out.string() << ": " << s.done << " of " << s.selected
              << " done";
    if (s.skipped_done > 0) std::cout << " (" << s.skipped_done << " already done earlier)";
    std::cout << ", " << s.failed << " failed; " << s.ran << " fitted in this run";
    if (s.taken_over > 0) std::cout << " (" << s.taken_over << " taken over from a process that died)";
    std::cout << ", " << duration_text(s.seconds) << "\n";
    std::cout << "results in " << (o.out / "fabrics").string() << "/<id>/, ledger "
              << batch::ledger_file(o.out).string() << " (yarnfit batch status " << o.out.string() << ")\n";
  }
  for (const auto& r : s.running_elsewhere) std::cerr << "running elsewhere, not touched: " << r << "\n";
  if (!s.failures.empty()) {
    std::cerr << s.failures.size() << " failed fabric" << (s.failures.size() == 1 ? "" : "s")
              << (o.retry_failed ? "" : " (rerun with --retry-failed to try them again)") << ":\n";
    for (const auto& f : s.failures) {
      std::cerr << "  " << f.fabric_id << ":\n";
      std::istringstream lines(f.error);
      for (std::string line; std::getline(lines, line);) std::cerr << "    " << line << "\n";
    }
  }
  if (s.interrupted) std::cerr << "batch interrupted: run the same command again to continue\n";
  if (!a.no_report) {
    // The report of the whole batch folder (every fabric of its ledger, not only this run's).
    try {
      const fs::path index = batch::write_batch_report(o.out);
      if (!a.quiet) std::cout << "report: open " << fs::absolute(index).lexically_normal().string() << "\n";
    } catch (const std::exception& e) {
      std::cerr << "batch: the report could not be written: " << e.what() << "\n";
      return k_exit_internal;
    }
  }
  return s.exit_code();
}

std::string cell(double v, int digits = 3) { return std::isfinite(v) ? db::format_g(v, digits) : "-"; }

int run_status(const std::string& dir, bool as_json) {
  try {
    const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(dir));
    const nlohmann::json j = batch::batch_status_json(ledger);
    if (as_json) {
      std::cout << j.dump(2) << "\n";
      return k_exit_ok;
    }
    const auto& c = j["counts"];
    std::cout << j["ledger"].get<std::string>() << ": " << j["jobs"].size() << " fabrics: " << c["done"] << " done, "
              << c["failed"] << " failed, " << c["running"] << " running, " << c["queued"] << " queued\n";
    // Per fabric: its state and the headline error of each stage (SPEC §5 names).
    std::map<std::string, std::map<std::string, nlohmann::json>> results;
    for (const auto& r : j["results"]) results[r["fabric_id"]][r["stage"]] = r;
    const auto pct = [&](const std::string& id, const char* stage, const char* key) {
      const auto& row = results[id][stage];
      return row.is_object() && row[key].is_number() ? cell(row[key].get<double>()) : std::string("-");
    };
    std::cout << std::left << std::setw(22) << "fabric" << std::setw(16) << "family" << std::setw(9) << "status"
              << std::setw(10) << "attempts" << std::setw(10) << "force %" << std::setw(10) << "compr %"
              << std::setw(11) << "comfort %" << "stage / error\n";
    for (const auto& job : j["jobs"]) {
      const std::string id = job["fabric_id"];
      std::string note = job["status"] == "running" && job["stage"].is_string() ? job["stage"].get<std::string>() : "";
      if (job["error"].is_string()) note = job["error"].get<std::string>().substr(0, job["error"].get<std::string>().find('\n'));
      std::cout << std::left << std::setw(22) << id << std::setw(16) << job["family"].get<std::string>() << std::setw(9)
                << job["status"].get<std::string>() << std::setw(10) << job["attempts"].get<int>() << std::setw(10)
                << pct(id, "shell", "stretch_force_pct") << std::setw(10) << pct(id, "shell", "compression_pct")
                << std::setw(11) << pct(id, "yarn", "stress_comfort_pct") << note << "\n";
    }
    return k_exit_ok;
  } catch (const Error& e) {
    std::cerr << e.what() << "\n";
    return exit_code_of(e);
  }
}

}  // namespace

void add_batch_commands(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<BatchArgs>();
  auto* b = app.add_subcommand(
      "batch", "Fit every fabric of a database (yarnfit fit's pipeline) as parallel jobs, on this machine or on MPI "
               "ranks (--mpi under mpirun); DIR/batch.db records every job and its results, DIR/fabrics/<id>/ holds "
               "the files of `fit`; rerunning the same command resumes (done fabrics skipped, changed ones redone, "
               "interrupted ones continued inside their yarn fit: the swarm stage or local run they were in). Exit 0 all done, 1 some failed, 2 bad arguments");
  b->add_option("DB", a->batch.database, "Database folder (one sub-folder per fabric)");
  b->add_option("-o,--out", a->batch.out, "Batch folder: batch.db, batch.lock and fabrics/<id>/");
  b->add_option("--jobs", a->batch.jobs, "Fabrics fitted at once, each in its own process")->capture_default_str();
  b->add_option("--threads-per-job", a->batch.threads_per_job, "OpenMP threads of each fabric's fit")
      ->capture_default_str();
  b->add_option("--family", a->batch.family, "Only the fabrics of this family");
  b->add_option("--only", a->batch.only, "Only these fabric ids (comma-separated)")->delimiter(',');
  for (const auto group : {pipeline::RequestGroup::stages, pipeline::RequestGroup::search, pipeline::RequestGroup::shell, pipeline::RequestGroup::outputs})
    add_request_options(*b, a->fit, group);
  b->add_flag("--no-report", a->no_report, "Do not write the HTML report DIR/report/ when the batch ends");
  b->add_flag("--retry-failed", a->batch.retry_failed, "Run the fabrics that failed before again (same hash)");
  b->add_flag("--mpi", a->mpi,
              std::string("Under mpirun: rank 0 keeps the ledger, the other ranks fit") +
                  (batch::mpi_available() ? "" : " (this build has no MPI)"));
  b->add_flag("-q,--quiet", a->quiet, "No progress line or summary (failures still go to stderr)");

  auto status = std::make_shared<std::pair<std::string, bool>>();
  auto* st = b->add_subcommand("status", "Print the ledger DIR/batch.db: every job, its state, attempts, headline "
                                         "errors; --json for everything, results included");
  st->add_option("DIR", status->first, "Batch folder")->required();
  st->add_flag("--json", status->second, "Print JSON");
  st->callback([status, &exit_code] { exit_code = run_status(status->first, status->second); });

  b->callback([a, b, st, &exit_code] {
    if (st->parsed()) return;
    if (a->batch.database.empty() || a->batch.out.empty()) {
      std::cerr << b->get_name() << ": " << (a->batch.database.empty() ? "DB" : "--out") << " is required\n";
      exit_code = k_exit_invalid_input;
      return;
    }
    exit_code = run_batch_command(*a);
  });
}

}  // namespace yarnfit::cli
