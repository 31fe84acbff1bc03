// Every output written through faults (issue 52): a full disk (RLIMIT_FSIZE), a folder the
// writer may not write into, and a kill between the temporary file and the rename. After each,
// no file is half-written, nothing the user had is lost, the message names the file and the
// reason, and a re-run finishes the work. One test per output: a fit's result files, the
// report, the exports, the fit's checkpoints, the batch ledger, the service's accounts and its
// uploads.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>

#include "batch/ledger.hpp"
#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "exports/export_fit.hpp"
#include "pipeline/outputs.hpp"
#include "reports/collection/fit_outputs.hpp"
#include "reports/collection/report_data.hpp"
#include "reports/report.hpp"
#include "results/yarn_fit_file.hpp"
#include "service/accounts/accounts.hpp"
#include "service/upload/archive_upload.hpp"
#include "swarm/swarm_state.hpp"
#include "tests/example_fabric.hpp"
#include "tests/exports/kept_fits.hpp"
#include "tests/reliability/write_faults.hpp"

namespace yarnfit::testing {
namespace {

namespace fs = std::filesystem;

// The message of what `write` threw (empty when it did not throw).
std::string thrown_by(const std::function<void()>& write) {
  try {
    write();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// The whole-file writers' faults, for an output `write` puts under `out`:
//  1. a full disk on the first run: the error names `named` and the reason; nothing half-written
//     (each file there is the one the re-run writes), no temporary file left;
//  2. the re-run finishes;
//  3. a full disk, a read-only folder and a kill before the rename on a later run: the files of
//     the finished run stay as they were, byte for byte; the kill leaves its temporary file,
//     which the next run removes;
//  4. that run finishes again, with the same bytes.
// A U3M material names itself by a new UUID and the time of writing; its other lines must match.
std::map<std::string, std::string> without_stamps(std::map<std::string, std::string> files) {
  for (auto& [name, bytes] : files) {
    if (!name.ends_with(".u3m")) continue;
    std::string kept;
    std::size_t at = 0;
    while (at < bytes.size()) {
      const std::size_t end = std::min(bytes.find('\n', at), bytes.size());
      const std::string line = bytes.substr(at, end - at);
      if (!contains(line, "\"id\":") && !contains(line, "\"created\":") && !contains(line, "\"modified\":"))
        kept += line + "\n";
      at = end + 1;
    }
    bytes = kept;
  }
  return files;
}

void expect_whole_through_faults(const std::function<void()>& write, const fs::path& out, const std::string& named) {
  const auto files_under = [](const fs::path& folder) { return without_stamps(testing::files_under(folder)); };
  std::string why;
  {
    const FullDisk disk(64);
    why = thrown_by(write);
  }
  EXPECT_TRUE(contains(why, named) && contains(why, "File too large")) << "full disk, first run: " << why;
  EXPECT_TRUE(temporaries_under(out).empty());
  const auto after_fault = files_under(out);

  ASSERT_EQ(thrown_by(write), "") << "the re-run";
  const auto whole = files_under(out);
  ASSERT_FALSE(whole.empty());
  for (const auto& [name, bytes] : after_fault) EXPECT_EQ(bytes, whole.at(name)) << name << " was half-written";

  {
    const FullDisk disk(64);
    why = thrown_by(write);
  }
  EXPECT_TRUE(contains(why, "File too large")) << "full disk, later run: " << why;
  EXPECT_EQ(files_under(out), whole) << "a full disk changed the finished run's files";

  const ChildEnd read_only = run_with_read_only_folder(out, write);
  EXPECT_TRUE(read_only.threw && contains(read_only.message, "Permission denied")) << read_only.message;
  EXPECT_EQ(files_under(out), whole) << "a read-only folder changed the finished run's files";

  const ChildEnd killed = run_killed_before_rename(write);
  EXPECT_TRUE(killed.killed) << killed.message;
  const auto left = temporaries_under(out);
  EXPECT_EQ(left.size(), 1u) << "the kill's temporary file";
  auto kept = files_under(out);
  for (const auto& name : left) kept.erase(name);
  EXPECT_EQ(kept, whole) << "a kill before the rename changed the finished run's files";

  ASSERT_EQ(thrown_by(write), "") << "the run after the kill";
  EXPECT_EQ(files_under(out), whole) << "the run after the kill: the same files, its temporary file removed";
}

TEST(WriteFaults, AFitsResultFilesStayWholeAndTheRerunFinishes) {
  const ScratchDir dir("wf_results");
  const auto yarn_fit = results::read_yarn_fit_file(exports::testing::k_data / "stockinette_demo_yarn_fit.json");
  const fs::path out = dir / "fit";
  expect_whole_through_faults([&] { (void)pipeline::write_yarn_outputs(yarn_fit, out); }, out, "yarn_fit.json");
}

TEST(WriteFaults, TheReportStaysWholeAndTheRerunFinishes) {
  const ScratchDir dir("wf_report");
  const ScratchDir fits("wf_report_fits");
  (void)exports::testing::fit_folder(fits, "stockinette_demo", true);
  const fs::path out = dir / "report";
  expect_whole_through_faults(
      [&] { (void)reports::write_report(reports::make_report_data({reports::read_fit_folders(fits.path())}), out, "today"); },
      out, "report.json");
}

TEST(WriteFaults, EveryExportStaysWholeAndTheRerunFinishes) {
  const ScratchDir dir("wf_exports");
  const fs::path fit = exports::testing::fit_folder(dir, "stockinette_demo", true);
  for (const auto format : {exports::ExportFormat::u3m, exports::ExportFormat::arcsim, exports::ExportFormat::table}) {
    SCOPED_TRACE(exports::to_string(format));
    const fs::path out = dir / exports::to_string(format);
    fs::create_directories(out);
    exports::ExportRequest request;
    request.fit_dir = fit;
    request.format = format;
    request.out = format == exports::ExportFormat::arcsim ? out / "demo.json" : out / "material";
    request.record = bundled_example_folder();
    request.overwrite = true;
    expect_whole_through_faults([&] { (void)exports::export_fit(request); }, out, out.string());
  }
}

TEST(WriteFaults, TheFitsCheckpointsStayWholeAndTheRerunFinishes) {
  const ScratchDir dir("wf_checkpoints");
  yarn::FitCheckpoint checkpoint;
  Eigen::VectorXd point(5);
  point << 12.0, 0.005, 1e-8, 2e-4, 9e5;
  checkpoint.rescored = std::vector<yarn::GlobalCandidate>{{point, 0.25}};
  checkpoint.local = {std::nullopt};
  const fs::path fit_out = dir / "fit";
  fs::create_directories(fit_out);
  expect_whole_through_faults([&] { yarn::write_fit_checkpoint(fit_out / "fit_checkpoint.json", checkpoint); },
                              fit_out, "fit_checkpoint.json");

  const swarm::ParameterSpace space({{"a", 0.0, 1.0, false}, {"b", 1.0, 10.0, true}});
  swarm::detail::SwarmState state;
  state.settings.particles = 3;
  state.iterations_done = 1;
  swarm::IterationRecord first;
  first.iteration = 1;
  first.best_value = first.iteration_best = 1.0;
  state.summary.history = {first};
  state.position = Eigen::MatrixXd::Constant(2, 3, 0.5);
  state.velocity = Eigen::MatrixXd::Zero(2, 3);
  state.best_position = state.position;
  state.best_value = Eigen::VectorXd::Constant(3, 1.0);
  state.global_best = state.position.col(0);
  const fs::path swarm_out = dir / "swarm";
  fs::create_directories(swarm_out);
  expect_whole_through_faults([&] { swarm::detail::write_checkpoint(swarm_out / "fit_checkpoint.json.all", space, state); },
                              swarm_out, "fit_checkpoint.json.all");
  EXPECT_EQ(swarm::detail::read_checkpoint(swarm_out / "fit_checkpoint.json.all", space).settings.particles, 3);
}

// SQLite's own integrity check of a database file.
std::string integrity_of(const fs::path& file) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  std::string result = "cannot open";
  sqlite3_stmt* st = nullptr;
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
    result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return result;
}

TEST(WriteFaults, TheLedgerKeepsItsLastWholeStateAndTheRerunFinishes) {
  const ScratchDir dir("wf_ledger");
  const fs::path file = dir / "batch.db";
  batch::JobRow job;
  job.fabric_id = "demo";
  job.family = "jersey";
  job.folder = "fabrics/demo";
  job.status = "running";
  // Results big enough that the finishing transaction must grow the file.
  std::vector<batch::ResultRow> rows;
  for (const char* stage : {"shell", "yarn"}) {
    batch::ResultRow r{"demo", stage, "jersey", std::vector<double>(batch::result_columns().size(), 0.5),
                       "{\"note\": \"" + std::string(20000, 'x') + "\"}"};
    rows.push_back(r);
  }
  {
    batch::Ledger ledger(file);
    ledger.put_job(job, "queued", "", 1.0);
  }
  const auto size = static_cast<rlim_t>(fs::file_size(file));
  std::string why;
  {
    batch::Ledger ledger(file);
    const FullDisk disk(size);
    why = thrown_by([&] { ledger.finish_job("demo", true, "", rows, 2.0); });
  }
  EXPECT_TRUE(contains(why, "batch.db") || contains(why, "ledger")) << why;
  EXPECT_FALSE(why.empty()) << "the finishing transaction did not meet the full disk";
  EXPECT_EQ(integrity_of(file), "ok");
  {
    const auto ledger = batch::Ledger::open_read_only(file);
    ASSERT_TRUE(ledger.job("demo"));
    EXPECT_EQ(ledger.job("demo")->status, "running") << "a job marked done without its results";
    EXPECT_TRUE(ledger.results().empty()) << "results recorded by a transaction that failed";
  }
  {
    const ChildEnd read_only = run_with_read_only_folder(dir.path(), [&] {
      batch::Ledger ledger(file);
      ledger.finish_job("demo", true, "", rows, 2.0);
    });
    EXPECT_TRUE(read_only.threw) << "a read-only folder: " << read_only.message;
  }
  EXPECT_EQ(integrity_of(file), "ok");
  {
    batch::Ledger ledger(file);
    ASSERT_EQ(thrown_by([&] { ledger.finish_job("demo", true, "", rows, 3.0); }), "");
  }
  const auto ledger = batch::Ledger::open_read_only(file);
  EXPECT_EQ(ledger.job("demo")->status, "done");
  EXPECT_EQ(ledger.results().size(), 2u);
}

TEST(WriteFaults, TheAccountsKeepTheirUsersAndTheRerunFinishes) {
  const ScratchDir dir("wf_accounts");
  const fs::path file = dir / "accounts.db";
  std::string token;
  {
    service::Accounts accounts(file);
    token = accounts.add_user("ana", false).token;
  }
  const auto size = static_cast<rlim_t>(fs::file_size(file));
  std::string why;
  {
    service::Accounts accounts(file);
    const FullDisk disk(size);
    for (int i = 0; i < 200 && why.empty(); ++i) why = thrown_by([&] { (void)accounts.add_user("user" + std::to_string(i), false); });
  }
  EXPECT_FALSE(why.empty()) << "the accounts never met the full disk";
  EXPECT_EQ(integrity_of(file), "ok");
  service::Accounts accounts(file);
  EXPECT_TRUE(accounts.authenticate(token)) << "ana's token stopped working";
  EXPECT_EQ(thrown_by([&] { (void)accounts.add_user("bob", false); }), "");
}

TEST(WriteFaults, AnUploadIsKeptWholeOrNotAtAllAndTheRetryFinishes) {
  const ScratchDir dir("wf_upload");
  // The bundled example as a tar archive, made by tar itself.
  const fs::path archive = dir / "record.tar";
  ASSERT_EQ(std::system(("tar -cf " + quoted(archive) + " -C " + quoted(bundled_example_folder().parent_path()) +
                         " stockinette_demo")
                            .c_str()),
            0);
  const std::string bytes = read_file(archive);
  service::UnpackedUpload refused;
  {
    const FullDisk disk(256);
    refused = service::unpack_upload(bytes, dir / "staged");
  }
  EXPECT_FALSE(refused.ok);
  EXPECT_EQ(refused.refusal.status, 500) << refused.refusal.message;
  EXPECT_FALSE(fs::exists(dir / "staged")) << "a refused upload left files";
  const service::UnpackedUpload retried = service::unpack_upload(bytes, dir / "staged");
  ASSERT_TRUE(retried.ok) << retried.refusal.message;
  ASSERT_FALSE(retried.files.empty());
  for (const auto& name : retried.files)
    EXPECT_EQ(read_file(dir / "staged" / name), read_file(bundled_example_folder() / name)) << name;

  // Killed with every file unpacked and flushed, before the folder is moved into place.
  const ChildEnd killed = run_in_child(
      [] { service::detail::set_before_move_hook([](const fs::path&) { ::raise(SIGKILL); }); },
      [&] { (void)service::unpack_upload(bytes, dir / "killed"); });
  EXPECT_TRUE(killed.killed) << killed.message;
  EXPECT_FALSE(fs::exists(dir / "killed")) << "a killed upload is in place";
  const auto hidden = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir.path()))
      if (e.path().filename().string().starts_with(".")) names.push_back(e.path().filename().string());
    return names;
  };
  EXPECT_EQ(hidden().size(), 1u) << "the killed unpacker's staging folder is what it leaves";
  const service::UnpackedUpload again = service::unpack_upload(bytes, dir / "killed");
  ASSERT_TRUE(again.ok) << again.refusal.message;
  EXPECT_EQ(again.files, retried.files);
  for (const auto& name : again.files)
    EXPECT_EQ(read_file(dir / "killed" / name), read_file(bundled_example_folder() / name)) << name;
  EXPECT_TRUE(hidden().empty()) << "the retry left the dead unpacker's staging folder";
}

}  // namespace
}  // namespace yarnfit::testing
