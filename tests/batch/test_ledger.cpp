// The batch's building blocks: the ledger's transactions and schema, and job hashes that
// change with every input they cover and only with those, and that stay the ones ledgers
// already hold (SHA-256 itself: test_sha256.cpp).
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <limits>

#include "batch/batch_options.hpp"
#include "fabrics_db/records/fabric_hash.hpp"
#include "batch/ledger.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::testing {
namespace {

std::string journal_mode(const fs::path& file) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, nullptr);
  std::string mode;
  if (sqlite3_step(st) == SQLITE_ROW) mode = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(db);
  return mode;
}

TEST(Ledger, KeepsJobsResultsAndEventsAcrossReopeningInWalMode) {
  ScratchDir dir("ledger");
  const fs::path file = dir / "batch.db";
  {
    batch::Ledger ledger(file);
    batch::JobRow job;
    job.fabric_id = "A1";
    job.family = "rib";
    job.folder = "/db/A1";
    job.hash = "h1";
    job.options = "{}";
    job.status = "queued";
    ledger.put_job(job, "queued", "h1", 100.0);
    ledger.start_job("A1", "hostx", 4242, 101.0);
    ledger.set_stage("A1", "swarm", 102.0);
    batch::ResultRow row{"A1", "yarn", "rib", std::vector<double>(batch::result_columns().size(),
                                                                   std::numeric_limits<double>::quiet_NaN()),
                         R"({"ks1":1.5})"};
    row.values[1] = 4.25;  // stretch_force_pct
    ledger.finish_job("A1", true, "", {row}, 110.0);
  }
  EXPECT_EQ(journal_mode(file), "wal");
  const batch::Ledger ledger = batch::Ledger::open_read_only(file);
  const auto job = ledger.job("A1");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, "done");
  EXPECT_EQ(job->attempts, 1);
  EXPECT_EQ(job->host, "hostx");
  EXPECT_EQ(job->pid, 4242);
  EXPECT_EQ(job->started, 101.0);
  EXPECT_EQ(job->ended, 110.0);
  EXPECT_TRUE(job->stage.empty());
  const auto results = ledger.results();
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].values[1], 4.25);
  EXPECT_TRUE(std::isnan(results[0].values[0]));  // NULL comes back as NaN
  EXPECT_EQ(results[0].params, R"({"ks1":1.5})");
  std::vector<std::string> events;
  for (const auto& e : ledger.events()) events.push_back(e.event);
  EXPECT_EQ(events, (std::vector<std::string>{"queued", "started", "done"}));
  EXPECT_ERROR(batch::Ledger::open_read_only(dir / "none.db"), yarnfit::ErrorCategory::input);
}

TEST(Ledger, AFailedTransactionLeavesNothingBehind) {
  ScratchDir dir("ledger-tx");
  batch::Ledger ledger(dir / "batch.db");
  batch::JobRow job;
  job.fabric_id = "A1";
  job.folder = "/db/A1";
  job.hash = "h";
  job.options = "{}";
  job.status = "bogus";  // violates the CHECK constraint
  EXPECT_ERROR(ledger.put_job(job, "queued", "", 1.0), yarnfit::ErrorCategory::io);
  EXPECT_FALSE(ledger.job("A1"));
  EXPECT_TRUE(ledger.events().empty());  // the event was in the same transaction
  job.status = "queued";
  ledger.put_job(job, "queued", "", 2.0);
  EXPECT_TRUE(ledger.job("A1"));
}

TEST(FabricHash, ChangesWithTheRecordItsCurvesAndTheOptionsButNotWithThreads) {
  ScratchDir dir("hash");
  const fs::path fabric = dir / "demo";
  fs::copy(bundled_example_folder(), fabric, fs::copy_options::recursive);
  pipeline::PipelineOptions o;
  const auto hash = [&] { return db::fabric_hash(db::load_fabric(fabric), batch::fit_options_json(o)); };
  const std::string h0 = hash();
  EXPECT_EQ(h0.size(), 64u);
  EXPECT_EQ(hash(), h0);
  o.shell.threads = 7;
  o.yarn.threads = 3;
  EXPECT_EQ(hash(), h0);  // threads change the time, not the results
  o.yarn.particles = 17;
  const std::string h1 = hash();
  EXPECT_NE(h1, h0);
  o.yarn.particles = pipeline::PipelineOptions{}.yarn.particles;
  EXPECT_EQ(hash(), h0);
  // One byte of one curve.
  const fs::path csv = fabric / "stretch_weft.csv";
  ASSERT_TRUE(fs::exists(csv)) << csv;
  std::string text = read_file(csv);
  text += "\n";
  write_file(csv, text);
  const std::string h2 = hash();
  EXPECT_NE(h2, h0);
  // The tile, which lives beside the record here.
  write_file(fabric / "tile.pyp", read_file(fabric / "tile.pyp") + "\n");
  EXPECT_NE(hash(), h2);
}

// A ledger written by an earlier yarnfit holds hashes of this form; a batch resumes it only if
// the same record and options still hash to the same digest. The digest was computed by the
// hand-written SHA-256 the batch used before OpenSSL, and by Python's hashlib, over the
// length-prefixed fields fabric_hash feeds (a broken record: every file of its folder).
TEST(FabricHash, IsTheDigestEarlierLedgersHold) {
  ScratchDir dir("hashpin");
  const fs::path fabric = dir / "pinned";
  write_file(fabric / "fabric.yaml", "# not a fabric record: the hash covers every file of a broken one\nid: pinned\n");
  write_file(fabric / "notes" / "readme.txt", std::string("a line\nand a second, with a NUL: \0 and the end\n", 47));
  const db::FabricLoad load = db::load_fabric(fabric);
  ASSERT_FALSE(load.fabric);
  EXPECT_EQ(db::fabric_hash(load, nlohmann::json{{"particles", 64}}),
            "c25235a4903fc2f398d948bd7b0e9d23a1d654600434ae7a74083888444bdd31");
}

}  // namespace
}  // namespace yarnfit::testing
