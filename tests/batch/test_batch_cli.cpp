// `yarnfit batch` end to end (issue 18's acceptance): a database made in the test — three
// fabrics from `synth yarn` on the stockinette tile of ../shared, one from `synth shell` given
// that tile and a yarn, and one broken record — fitted with a small swarm.
//   - the four are done, the broken one is failed with a reason naming its file and line,
//     exit 1, and the results table holds the four fabrics' errors and parameters;
//   - a batch killed with SIGKILL inside a fabric's swarm and run again ends with results
//     bitwise identical to an uninterrupted batch (and to one with another number of jobs);
//     the ledger shows no fabric lost and none finished twice;
//   - editing one fabric's CSV redoes that fabric only;
//   - under mpirun (3 ranks) the same results, and the same after a kill.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>

#include "batch/batch.hpp"
#include "batch/ledger.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "numerics/util/error.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::testing {
namespace {

using nlohmann::json;


// Small enough for a unit test, large enough that a swarm has iterations to be killed in. The
// tile's own rest shape (--no-rest-shape) halves each candidate's time; what is tested is the
// batch around the fits, which the rest shape does not change. The thesis's single swarm with a
// stencil local step keeps the fits this small (the staged fit's own resume is tested in
// tests/yarn_fit/fit/test_staged_fit.cpp).
const std::string k_small =
    " --global swarm --local implicit-filtering --particles 3 --iterations 2 --samples 2 --local-samples 3"
    " --local-evaluations 3 --no-profile --no-rest-shape --threads-per-job 1 --quiet";

const char* const k_good[] = {"knit_a", "knit_b", "knit_c", "shell_d"};

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

class BatchCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(shared_stockinette())) return;
    s_dir = std::make_unique<ScratchDir>("batchcli");
    const fs::path db = *s_dir / "db";
    fs::create_directories(db);
    db::Problems problems;
    const auto tile = db::read_pyp(shared_stockinette(), problems);
    ASSERT_TRUE(tile) << problems.to_string();
    const auto params = yarn::default_params({400.0, db::compute_tile_facts(*tile).r_est});
    write_file(*s_dir / "a.yaml", yarn::to_json(params).dump(2) + "\n");
    yarn::YarnParams stiffer = params;
    stiffer.ks1 *= 2.0;
    stiffer.kb *= 0.5;
    write_file(*s_dir / "b.yaml", yarn::to_json(stiffer).dump(2) + "\n");
    const auto synth = [&](const char* id, const char* family, const char* yaml, const char* stretch) {
      const fs::path src = *s_dir / (std::string("src_") + id);
      const auto r = run_cli("synth yarn --pattern " + quoted(shared_stockinette()) + " --params " + quoted(*s_dir / yaml) +
                             " --out " + quoted(src) + " --id " + id + " --family " + family + " --max-stretch " +
                             stretch + " --directions weft --points 4 -q");
      ASSERT_EQ(r.exit_code, 0) << r.err;
      fs::copy(src / "fabric", db / id, fs::copy_options::recursive);
    };
    synth("knit_a", "soft", "a.yaml", "0.15");
    synth("knit_b", "soft", "b.yaml", "0.15");
    synth("knit_c", "firm", "a.yaml", "0.12");
    // A shell-model record (its curves from the thesis model), given the tile and a yarn so
    // that the yarn stage can run on its targets.
    const auto r = run_cli("synth shell --out " + quoted(db / "shell_d") +
                           " --id shell_d --family firm --weft 0.15 --bias 0 --warp 0 --points 5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    fs::copy_file(db / "knit_a" / "tile.pyp", db / "shell_d" / "tile.pyp");
    std::string yaml = replace_once(read_file(db / "shell_d" / "fabric.yaml"), "mass_fraction: 1.0",
                                    "mass_fraction: 1.0\n    stiffness_N: 400");
    yaml += "\npattern: {file: tile.pyp, weft_axis: x}\n";
    write_file(db / "shell_d" / "fabric.yaml", yaml);
    // The broken record: a copy of knit_a with a word where line 3 of its curve has a force.
    fs::copy(db / "knit_a", db / "broken_e", fs::copy_options::recursive);
    write_file(db / "broken_e" / "fabric.yaml",
               replace_once(read_file(db / "broken_e" / "fabric.yaml"), "id: knit_a", "id: broken_e"));
    std::string csv = read_file(db / "broken_e" / "stretch_weft.csv");
    const auto line3 = csv.find('\n', csv.find('\n') + 1) + 1;
    const auto comma = csv.find(',', line3);
    csv.replace(comma + 1, csv.find_first_of(",\n", comma + 1) - comma - 1, "lots");
    write_file(db / "broken_e" / "stretch_weft.csv", csv);
  }
  static void TearDownTestSuite() { s_dir.reset(); }
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(shared_stockinette());
    ASSERT_TRUE(s_dir && fs::exists(db() / "shell_d" / "fabric.yaml")) << "the test database was not made";
  }
  static fs::path db() { return *s_dir / "db"; }
  static std::string batch(const fs::path& out, const std::string& extra = "") {
    return "batch " + quoted(db()) + " --out " + quoted(out) + k_small + extra;
  }
  static std::unique_ptr<ScratchDir> s_dir;
};

std::unique_ptr<ScratchDir> BatchCli::s_dir;

// The results of a batch folder that must not depend on how it ran: the ledger's results
// without their timings, and every output file without the ones that hold times or paths.
struct Results {
  std::map<std::string, std::vector<double>> rows;  // "fabric/stage" → values (seconds dropped)
  std::map<std::string, std::string> params;        // "fabric/stage" → params JSON
  std::map<std::string, std::string> files;         // "fabric/file" → content
};

Results results_of(const fs::path& out) {
  Results r;
  const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  const auto& columns = batch::result_columns();
  for (const auto& row : ledger.results()) {
    std::vector<double> values;
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] != "seconds") values.push_back(row.values[i]);
    r.rows[row.fabric_id + "/" + row.stage] = values;
    r.params[row.fabric_id + "/" + row.stage] = row.params;
  }
  for (const auto& id : k_good) {
    const fs::path folder = out / "fabrics" / id;
    for (const char* f : {"uniform_targets.csv", "shell_curves.csv", "yarn_curves.csv"})
      r.files[std::string(id) + "/" + f] = fs::exists(folder / f) ? read_file(folder / f) : "(missing)";
    for (const char* f : {"shell_fit.json", "yarn_fit.json"}) {
      json j = json::parse(read_file(folder / f), nullptr, false);
      r.files[std::string(id) + "/" + f] =
          j.is_object() ? json{{"params", j["params"]}, {"errors", j["errors"]}, {"evaluations", j["evaluations"]}}.dump()
                        : "(unreadable)";
    }
  }
  return r;
}

// Bitwise: the doubles compared as they are (NaN equal to NaN, nothing else tolerated).
void expect_same_results(const Results& a, const Results& b) {
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (const auto& [key, values] : a.rows) {
    ASSERT_TRUE(b.rows.count(key)) << key;
    const auto& other = b.rows.at(key);
    ASSERT_EQ(values.size(), other.size());
    for (std::size_t i = 0; i < values.size(); ++i)
      EXPECT_TRUE(values[i] == other[i] || (std::isnan(values[i]) && std::isnan(other[i])))
          << key << " column " << i << ": " << values[i] << " vs " << other[i];
  }
  EXPECT_EQ(a.params, b.params);
  for (const auto& [key, text] : a.files) EXPECT_EQ(text, b.files.at(key)) << key;
}

std::map<std::string, int> done_events(const fs::path& out) {
  std::map<std::string, int> n;
  for (const auto& e : batch::Ledger::open_read_only(batch::ledger_file(out)).events())
    if (e.event == "done") ++n[e.fabric_id];
  return n;
}

// Starts `yarnfit ARGS` (or `PREFIX yarnfit ARGS`) in its own process group.
pid_t start_in_background(const std::string& prefix, const std::string& args, const fs::path& log) {
  const std::string cmd = "exec " + prefix + quoted(YARNFIT_CLI) + " " + args + " >" + quoted(log) + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// The stage the ledger records for a running `fabric` ("" when none yet).
std::string ledger_stage(const fs::path& out, const std::string& fabric) {
  try {
    const auto job = batch::Ledger::open_read_only(batch::ledger_file(out)).job(fabric);
    return job && job->status == "running" ? job->stage : "";
  } catch (const yarnfit::Error&) {
    return "";  // not created yet
  }
}

// Waits until `fabric`'s swarm has written a checkpoint, its yarn stage has not finished and
// the ledger says it is in its swarm (the batch writes the stage the fit reports through its
// pipe a moment after the fit wrote the checkpoint): the moment to kill a batch inside a
// swarm. False after `timeout` s or if `pid` ended.
bool wait_inside_swarm(const fs::path& out, const std::string& fabric, pid_t pid, double timeout) {
  const fs::path folder = out / "fabrics" / fabric;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout * k_wait_scale);
  while (std::chrono::steady_clock::now() < until) {
    if (fs::exists(folder / "swarm_checkpoint.json") && ledger_stage(out, fabric) == "swarm" &&
        !fs::exists(folder / "yarn_fit.json"))
      return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST_F(BatchCli, FitsTheGoodFabricsRecordsTheBrokenOneAndRedoesOnlyAnEditedFabric) {
  const fs::path out = *s_dir / "run1";
  auto r = run_cli(batch(out, " --jobs 2"));
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  // The broken record's reason names its file and line, on stderr and in the ledger.
  const std::string where = (db() / "broken_e" / "stretch_weft.csv").string() + ":3:";
  EXPECT_TRUE(contains(r.err, where)) << r.err;
  const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  const auto broken = ledger.job("broken_e");
  ASSERT_TRUE(broken);
  EXPECT_EQ(broken->status, "failed");
  EXPECT_TRUE(contains(broken->error, where)) << broken->error;
  EXPECT_EQ(broken->attempts, 0);  // never run
  EXPECT_FALSE(fs::exists(out / "fabrics" / "broken_e"));
  // The four are done, each with both stages' errors and parameters in the results table.
  const auto& columns = batch::result_columns();
  const auto col = [&](const std::string& name) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
  };
  std::map<std::string, batch::ResultRow> rows;
  for (const auto& row : ledger.results()) rows[row.fabric_id + "/" + row.stage] = row;
  EXPECT_EQ(rows.size(), 8u);
  for (const auto& id : k_good) {
    const auto job = ledger.job(id);
    ASSERT_TRUE(job) << id;
    EXPECT_EQ(job->status, "done") << id << ": " << job->error;
    EXPECT_EQ(job->attempts, 1) << id;
    const auto& shell = rows[std::string(id) + "/shell"];
    const auto& yarn = rows[std::string(id) + "/yarn"];
    for (const char* c : {"stretch_force_pct", "kxx", "kyy", "kss", "seconds"})
      EXPECT_TRUE(std::isfinite(shell.values.at(col(c)))) << id << " shell " << c;
    for (const char* c : {"stress_comfort_pct", "stress_full_pct", "compression_pct", "ks1", "eps_s", "kb", "R1",
                          "kc1", "ks2", "evaluations"})
      EXPECT_TRUE(std::isfinite(yarn.values.at(col(c)))) << id << " yarn " << c;
    EXPECT_EQ(yarn.family, id[0] == 'k' && id[5] != 'c' ? "soft" : "firm") << id;
    // The ledger's figures are the files' figures.
    const json y = json::parse(read_file(out / "fabrics" / id / "yarn_fit.json"));
    EXPECT_EQ(yarn.values.at(col("stress_comfort_pct")), y["errors"]["stress_comfort_pct"].get<double>());
    EXPECT_EQ(yarn.values.at(col("ks1")), y["params"]["ks1"].get<double>());
    for (const char* f : {"shell_fit.json", "uniform_targets.csv", "shell_curves.csv", "yarn_fit.json",
                          "yarn_curves.csv", "summary.txt", "swarm_checkpoint.json"})
      EXPECT_TRUE(fs::exists(out / "fabrics" / id / f)) << id << "/" << f;
  }
  // batch status says the same.
  r = run_cli("batch status " + quoted(out) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json status = json::parse(r.out);
  EXPECT_EQ(status["counts"]["done"], 4);
  EXPECT_EQ(status["counts"]["failed"], 1);
  r = run_cli("batch status " + quoted(out));
  EXPECT_TRUE(contains(r.out, "4 done, 1 failed")) << r.out;

  // The same command again: nothing to do but the failed record, which is not retried.
  const std::size_t events_before = ledger.events().size();
  r = run_cli(batch(out, " --jobs 2"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(batch::Ledger::open_read_only(batch::ledger_file(out)).events().size(), events_before);

  // One fabric's curve edited: that fabric, and only it, is fitted again.
  const fs::path csv = db() / "knit_b" / "stretch_weft.csv";
  const std::string original = read_file(csv);
  write_file(csv, original + "\n");
  r = run_cli(batch(out, " --jobs 2"));
  write_file(csv, original);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  std::map<std::string, int> started;
  const auto events = batch::Ledger::open_read_only(batch::ledger_file(out)).events();
  for (std::size_t i = events_before; i < events.size(); ++i)
    if (events[i].event == "started") ++started[events[i].fabric_id];
  EXPECT_EQ(started, (std::map<std::string, int>{{"knit_b", 1}}));
  EXPECT_EQ(batch::Ledger::open_read_only(batch::ledger_file(out)).job("knit_b")->status, "done");
}

TEST_F(BatchCli, AKilledBatchResumesToBitwiseTheResultsOfAnUninterruptedOne) {
  const std::string only = " --only knit_a,knit_b,shell_d";
  const fs::path reference = *s_dir / "reference";
  auto r = run_cli(batch(reference, only + " --jobs 2"));
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // One job at a time; SIGKILL to the batch process once knit_b is inside its swarm.
  const fs::path out = *s_dir / "killed";
  const pid_t pid = start_in_background("", batch(out, only + " --jobs 1"), *s_dir / "killed.log");
  ASSERT_TRUE(wait_inside_swarm(out, "knit_b", pid, 300)) << read_file(*s_dir / "killed.log");
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  {
    const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
    EXPECT_EQ(ledger.job("knit_a")->status, "done");
    const auto b = ledger.job("knit_b");
    EXPECT_EQ(b->status, "running");  // as the killed batch left it
    EXPECT_EQ(b->stage, "swarm");
    EXPECT_EQ(ledger.job("shell_d")->status, "queued");
  }
  EXPECT_FALSE(fs::exists(out / "fabrics" / "knit_b" / "yarn_fit.json"));

  r = run_cli(batch(out, only + " --jobs 1"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_same_results(results_of(reference), results_of(out));
  const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  // None lost, none finished twice; knit_b taken over and run twice, the others once.
  EXPECT_EQ(done_events(out), (std::map<std::string, int>{{"knit_a", 1}, {"knit_b", 1}, {"shell_d", 1}}));
  EXPECT_EQ(ledger.job("knit_a")->attempts, 1);
  EXPECT_EQ(ledger.job("knit_b")->attempts, 2);
  EXPECT_EQ(ledger.job("shell_d")->attempts, 1);
  int taken_over = 0;
  for (const auto& e : ledger.events()) taken_over += e.event == "taken_over" && e.fabric_id == "knit_b";
  EXPECT_EQ(taken_over, 1);
  // The resumed swarm continued from its checkpoint rather than starting again.
  const json y = json::parse(read_file(out / "fabrics" / "knit_b" / "yarn_fit.json"));
  EXPECT_TRUE(y["settings"].contains("resumed_from")) << y["settings"].dump();
}

// OpenMPI refuses to run as root unless told; CI runs as root.
const std::string k_mpirun =
    "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
    "mpirun --oversubscribe -np 3 ";

TEST_F(BatchCli, UnderMpiTheResultsAreTheLocalOnesAlsoAfterAKill) {
  if (!batch::mpi_available()) {
    if (running_in_ci()) FAIL() << "this build has no MPI (CI=true: the install script installs OpenMPI)";
    GTEST_SKIP() << "built without MPI";
  }
  const std::string only = " --only knit_a,shell_d";
  const fs::path local = *s_dir / "local";
  auto r = run_cli(batch(local, only + " --jobs 2"));
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const fs::path mpi = *s_dir / "mpi";
  const int code = std::system((k_mpirun + quoted(YARNFIT_CLI) + " " + batch(mpi, only + " --mpi") + " >" +
                                quoted(*s_dir / "mpi.log") + " 2>&1")
                                   .c_str());
  ASSERT_EQ(code, 0) << read_file(*s_dir / "mpi.log");
  expect_same_results(results_of(local), results_of(mpi));

  // Rank 0, the batch process that owns the ledger (batch.lock names it), killed with SIGKILL
  // inside a swarm: mpirun then ends the job, the workers with it. Run again.
  const fs::path killed = *s_dir / "mpi_killed";
  const pid_t pid = start_in_background(k_mpirun, batch(killed, only + " --mpi"), *s_dir / "mpi_killed.log");
  ASSERT_TRUE(wait_inside_swarm(killed, "knit_a", pid, 300)) << read_file(*s_dir / "mpi_killed.log");
  const std::string holder = read_file(killed / "batch.lock");  // "pid N on HOST"
  const long rank0 = std::stol(holder.substr(holder.find(' ') + 1));
  ASSERT_GT(rank0, 1);
  ::kill(static_cast<pid_t>(rank0), SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_NE(status, 0);  // mpirun reports the killed rank
  EXPECT_EQ(batch::Ledger::open_read_only(batch::ledger_file(killed)).job("knit_a")->status, "running");
  const int again = std::system((k_mpirun + quoted(YARNFIT_CLI) + " " + batch(killed, only + " --mpi") + " >" +
                                 quoted(*s_dir / "mpi_again.log") + " 2>&1")
                                    .c_str());
  ASSERT_EQ(again, 0) << read_file(*s_dir / "mpi_again.log");
  expect_same_results(results_of(local), results_of(killed));
  const auto done = done_events(killed);
  for (const char* id : {"knit_a", "shell_d"}) EXPECT_EQ(done.count(id) ? done.at(id) : 0, 1) << id;
}

TEST_F(BatchCli, BadArgumentsExit2AndASecondBatchOnTheSameFolderIsRefused) {
  auto r = run_cli("batch " + quoted(db()) + " --out " + quoted(*s_dir / "bad") + " --jobs 0 --stages yarn --only nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--stages")) << r.err;
  EXPECT_TRUE(contains(r.err, "jobs")) << r.err;
  r = run_cli("batch " + quoted(db()) + " --out " + quoted(*s_dir / "bad") + " --only nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "nope: no such fabric")) << r.err;
  r = run_cli("batch status " + quoted(*s_dir / "nowhere"));
  EXPECT_EQ(r.exit_code, 2);
  // While one batch runs, another on the same folder is refused and changes nothing; SIGTERM
  // then stops the first: its job goes back to the queue, exit 1.
  const fs::path out = *s_dir / "busy";
  const pid_t pid = start_in_background("", batch(out, " --only knit_c --jobs 1"), *s_dir / "busy.log");
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(out / "fabrics" / "knit_c") && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  r = run_cli(batch(out, " --only knit_c"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "another batch is running")) << r.err;
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << read_file(*s_dir / "busy.log");
  EXPECT_TRUE(contains(read_file(*s_dir / "busy.log"), "run the same command again")) << read_file(*s_dir / "busy.log");
  const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  EXPECT_EQ(ledger.job("knit_c")->status, "queued");
  EXPECT_EQ(ledger.events().back().event, "interrupted");
}

// A record naming a knit to generate is fitted: the batch checks it with the folder its jobs
// keep generated tiles in (it used to refuse every such record before any work, asking for a
// tile cache that only the jobs set).
// Issue 52's batch-level write fault: every results row of the ledger names a stage whose
// result file is there.
void expect_every_row_has_its_file(const fs::path& out) {
  for (const auto& row : batch::Ledger::open_read_only(batch::ledger_file(out)).results())
    EXPECT_TRUE(fs::exists(batch::fabric_output_folder(out, row.fabric_id) / (row.stage + "_fit.json")))
        << row.fabric_id << "/" << row.stage << ": a ledger row without its file";
}

TEST_F(BatchCli, AFabricFolderThatCannotBeWrittenFailsWithItsReasonAndTheRetryFinishes) {
  // The ledger's folder writable, the fabrics' folder not: the job fails writing its first
  // file. Root writes anywhere, so as root the batch runs as nobody.
  const fs::path out = *s_dir / "read_only_fabrics";
  fs::create_directories(out / "fabrics");
  fs::permissions(out, fs::perms::all);
  fs::permissions(out / "fabrics", fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                       fs::perms::others_read | fs::perms::others_exec);
  const std::string as_nobody = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
  if (::geteuid() != 0) fs::permissions(out / "fabrics", fs::perms::owner_write, fs::perm_options::remove);
  const pid_t pid = start_in_background(as_nobody, batch(out, " --only knit_a --jobs 1"), *s_dir / "ro.log");
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string log = read_file(*s_dir / "ro.log");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << log;
  {
    const auto ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
    const auto job = ledger.job("knit_a");
    ASSERT_TRUE(job);
    EXPECT_EQ(job->status, "failed");
    EXPECT_TRUE(contains(job->error, (out / "fabrics" / "knit_a").string())) << job->error;
    EXPECT_TRUE(contains(job->error, "Permission denied")) << job->error;
    EXPECT_TRUE(ledger.results().empty()) << "results recorded for a job that wrote nothing";
  }
  EXPECT_TRUE(contains(log, "Permission denied")) << log;
  expect_every_row_has_its_file(out);

  // Writable again: the retry finishes it, each row with its file.
  fs::permissions(out / "fabrics", fs::perms::owner_write, fs::perm_options::add);
  const auto r = run_cli(batch(out, " --only knit_a --jobs 1 --retry-failed"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  EXPECT_EQ(ledger.job("knit_a")->status, "done");
  EXPECT_EQ(ledger.results().size(), 2u);
  expect_every_row_has_its_file(out);
}

TEST(BatchGeneratedTile, ARecordNamingAKnitIsFittedOnItsGeneratedTile) {
  ScratchDir dir("batch_knit");
  write_base_fabric(dir / "db" / "K", "K");
  add_pattern_line(dir / "db" / "K", "{knit: stockinette, stitch_length_mm: 15.67, yarn_radius_mm: 1.2}");
  const fs::path out = dir / "out";
  const auto r = run_cli("batch " + quoted(dir / "db") + " --out " + quoted(out) + k_small + " --no-report");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const batch::Ledger ledger = batch::Ledger::open_read_only(batch::ledger_file(out));
  const auto job = ledger.job("K");
  ASSERT_TRUE(job);
  EXPECT_EQ(job->status, "done") << job->error;
  EXPECT_TRUE(fs::exists(out / "fabrics" / "K" / "yarn_fit.json"));
  int tiles = 0;
  for (const auto& e : fs::directory_iterator(batch::generated_tiles_folder(out)))
    tiles += e.path().extension() == ".pyp";
  EXPECT_EQ(tiles, 1);
}

}  // namespace
}  // namespace yarnfit::testing
