#pragma once
// The fitting service's jobs: a fit asked over HTTP is a job of the batch engine (batch/), not
// of a runner of the service's own. DATA_DIR/runs is a batch folder: its ledger
// DATA_DIR/runs/batch.db holds every job (keyed "<user>/<fabric id>"), each fit runs in a
// forked child as `yarnfit batch` runs it, writing DATA_DIR/runs/fabrics/<user>/<id>/ and
// checkpointing its swarm there. One batch runs for the service's whole life on its own
// thread, fed by start() and cancel() (batch::BatchFeed).
//
// What a request asked for is kept in DATA_DIR/runs/requests/<user>/<id>.json (written whole
// before start() answers): after a restart, even after kill -9, every job the ledger holds as
// queued or running is fed again, and the batch resumes it from its checkpoint (a job found
// running whose process is gone is taken over, as `batch` does).

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/jobs/fit_request_json.hpp"

namespace yarnfit::service {

struct FitJobsOptions {
  int jobs = 1;             // fits at once
  int threads_per_job = 2;  // OpenMP threads of each
  int active_per_user = 2;  // a user's jobs queued or running at once (429 past it)
  int queue_length = 32;    // jobs queued or running for everyone (429 past it)
  // Under mpirun (batch::MpiScope made by the caller, this is rank 0): the fits run on the
  // other ranks, each of which calls run_fit_worker, as `batch --mpi` runs them.
  bool mpi = false;
};

// What ranks 1…K−1 of a service under mpirun do: fit the jobs rank 0 hands them, each with the
// options its request (kept in DATA_DIR/runs/requests/) asked for, until rank 0 stops.
void run_fit_worker(const std::filesystem::path& data_dir, const FitJobsOptions& options);

// An answer of the job routes: HTTP status and JSON body.
struct JobAnswer {
  int status = 200;
  nlohmann::json body;
};

// Result files a job of fabric `id` can be asked for: each name and where it lies in the job's
// folder (the fit's files, and its exports: <id>.u3ma, <id>_arcsim.json and the table's files).
[[nodiscard]] std::vector<std::pair<std::string, std::filesystem::path>> downloadable_files(const std::string& id);

class FitJobs {
 public:
  // Starts the engine on DATA_DIR/runs and feeds it the jobs a previous run left queued or
  // running. Throws an Error when the engine cannot start (another service holds
  // DATA_DIR/runs).
  FitJobs(std::filesystem::path data_dir, FitJobsOptions options);
  // Stops the engine: running fits are killed and stay queued for the next start.
  ~FitJobs();
  FitJobs(const FitJobs&) = delete;
  FitJobs& operator=(const FitJobs&) = delete;

  // A fit of `owner`'s fabric `fabric_id` (its record in `record`): 202 with the job; 422 with
  // the request's problems; 409 when it is queued or running already; 429 past the limits.
  JobAnswer start(const std::string& owner, const std::string& fabric_id, const std::filesystem::path& record,
                  const nlohmann::json& body);
  // 200 with the job marked cancelled; 409 when it has ended; 404 when there is none.
  JobAnswer cancel(const std::string& owner, const std::string& fabric_id);

  // Deletes `owner`'s fabric `fabric_id`: its fit (ledger rows, kept request, result files) and
  // then its record folder `record`. 200 when gone; 409 while a fit of it is queued or
  // running (cancel it first). A start of a fit of it waits for the deletion, then finds no record.
  JobAnswer delete_fabric(const std::string& owner, const std::string& fabric_id, const std::filesystem::path& record);

  // The job of `owner`'s fabric as the API shows it: id, owner, state (queued, running, done,
  // failed, cancelled), stage, step, progress (0–1), seconds, seconds_left (null when not
  // known), attempts, error, files (the result files there are), report (true when written).
  [[nodiscard]] std::optional<nlohmann::json> job(const std::string& owner, const std::string& fabric_id) const;
  // Every job of `owner`, or of everyone when `owner` is empty.
  [[nodiscard]] std::vector<nlohmann::json> jobs(const std::string& owner) const;
  // Why fits cannot run (the engine stopped on an error); empty while they can.
  [[nodiscard]] std::string engine_problem() const;
  // Counts of jobs by state (for /metrics).
  [[nodiscard]] std::vector<std::pair<std::string, int>> counts() const;

  // The folder of the job's outputs.
  [[nodiscard]] std::filesystem::path output_folder(const std::string& owner, const std::string& fabric_id) const;
  // Writes the report over `owner`'s fabrics (everyone's when empty) into DATA_DIR/reports/
  // and returns its index.html.
  [[nodiscard]] std::filesystem::path family_report(const std::string& owner) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace yarnfit::service
