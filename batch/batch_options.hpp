#pragma once
// What `yarnfit batch` is asked to do (SPEC §5, §5a): every fabric of a database, fitted
// with the same options as `yarnfit fit`, as parallel jobs on this machine or on MPI ranks,
// its state in the ledger DIR/batch.db and its files in DIR/fabrics/<id>/.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "pipeline/pipeline.hpp"

namespace yarnfit::batch {

// A running fabric as the progress display shows it.
struct RunningFabric {
  std::string fabric_id;
  std::string stage;   // "shell", "swarm 3/10", "local 40/150", …
  double seconds = 0;  // since it started
};

// The batch's state after each change and about once a second.
struct BatchProgress {
  int selected = 0;  // fabrics this run is about
  int done = 0;      // including those done in earlier runs and skipped now
  int failed = 0;
  int queued = 0;
  std::vector<RunningFabric> running;
  double seconds = 0;        // since this run started
  double seconds_left = -1;  // estimate from the fabrics finished in this run; < 0 unknown
};
using BatchProgressFn = std::function<void(const BatchProgress&)>;

// A fabric given by its folder rather than found in a database (the fitting service's jobs):
// its ledger key (also its folder under DIR/fabrics/, so it may hold a '/'), its record, and
// its own fit options and report.
struct BatchFabric {
  std::string key;
  std::filesystem::path folder;
  pipeline::PipelineOptions fit;
  bool report = false;  // the one-fabric report in its output folder (report/)
};

// Work that reaches a batch while it runs (the fitting service). With a feed the batch does
// not end when its queue is empty: it asks `take` for new fabrics about four times a second,
// stops the ones `cancelled` names (queued or running: recorded as failed, "cancelled"), and
// ends when `stop` says so (running jobs back to queued, as on SIGINT). Called on the thread
// that runs the batch.
// The error the ledger records for a job its feed cancelled.
inline constexpr const char* k_cancelled_by_owner = "cancelled by its owner";

struct BatchFeed {
  std::function<std::vector<BatchFabric>()> take;
  std::function<std::vector<std::string>()> cancelled;
  std::function<bool()> stop;
  [[nodiscard]] explicit operator bool() const { return static_cast<bool>(take); }
};

struct BatchOptions {
  std::filesystem::path database;  // may be empty when a feed gives the fabrics
  std::filesystem::path out;
  int jobs = 1;             // fabrics fitted at once (local mode)
  int threads_per_job = 2;  // OpenMP threads of each fabric's fit
  std::string family;                // only this family (empty: all)
  std::vector<std::string> only;     // only these fabric ids (empty: all)
  pipeline::PipelineOptions fit;     // stages, shell and yarn settings (threads are set per job)
  bool retry_failed = false;
  double heartbeat_interval = 2.0;   // [s] between heartbeats of running jobs
  // A running job whose heartbeat is older than this [s] belongs to a process that died
  // (on this host a dead pid is enough).
  double stale_after = 60.0;
  BatchProgressFn progress;
  BatchFeed feed;
  // The options of a fed fabric, looked up by its key where a job arrives without them (an MPI
  // worker is sent the key only); the batch's `fit` when empty or when it finds none.
  std::function<std::optional<BatchFabric>(const std::string& key)> fabric_of;

  // Every invalid field ("jobs", "threads_per_job", "fit.…"); empty when usable.
  [[nodiscard]] db::Problems problems() const;
};

// The options that decide a fabric's results, as JSON (part of each job's hash): the stages,
// the shell options and the yarn settings, but not threads or jobs, which change the time
// and not the results.
[[nodiscard]] nlohmann::json fit_options_json(const pipeline::PipelineOptions& options);

// Where a fabric's files go, and its swarm checkpoint.
[[nodiscard]] std::filesystem::path fabric_output_folder(const std::filesystem::path& out, const std::string& fabric_id);
[[nodiscard]] std::filesystem::path swarm_checkpoint_file(const std::filesystem::path& fabric_folder);
[[nodiscard]] std::filesystem::path ledger_file(const std::filesystem::path& out);
// Where the tiles of records with a knit to generate are kept: shared by every fabric of the
// batch (fabrics of one knit and scale reuse one tile).
[[nodiscard]] std::filesystem::path generated_tiles_folder(const std::filesystem::path& out);

}  // namespace yarnfit::batch
