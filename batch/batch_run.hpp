#pragma once
// What the local and the MPI batch share: checking the options, holding DIR, planning the
// jobs from the database and the ledger, recording each finished job with its results, and
// the progress figures. The two differ only in where a job runs (batch/local_batch.cpp,
// batch/mpi_batch.cpp).

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "batch/batch.hpp"
#include "batch/fabric_job.hpp"
#include "batch/ledger.hpp"

namespace yarnfit::batch {

// DIR/batch.lock, held (flock) from construction to destruction; throws an Error naming the
// holder when another batch has it.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::filesystem::path& out);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;
  // The lock's descriptor, for a forked child to close.
  [[nodiscard]] int fd() const { return m_fd; }

 private:
  int m_fd = -1;
};

class BatchRun {
 public:
  // Checks the options, takes DIR, opens the ledger and plans every selected fabric (recording
  // the invalid ones as failed). Throws an Error when nothing can be run.
  explicit BatchRun(const BatchOptions& options);

  [[nodiscard]] const BatchOptions& options() const { return m_options; }
  [[nodiscard]] Ledger& ledger() { return m_ledger; }
  [[nodiscard]] const DirectoryLock& lock() const { return *m_lock; }
  [[nodiscard]] bool has_queued() const { return !m_queue.empty(); }
  [[nodiscard]] std::size_t running_count() const { return m_running.size(); }
  [[nodiscard]] std::vector<std::string> running_ids() const;

  // A fabric the feed brought: planned as the database's are (run, resumed, or left done), but
  // a failed one runs again (it was asked for anew). One already running goes on.
  void add(const BatchFabric& fabric);
  // Ends a queued or running job as failed with `why` (the caller has stopped its process).
  void cancel(const std::string& key, const std::string& why);
  [[nodiscard]] bool is_running(const std::string& key) const { return m_running.count(key) > 0; }

  // The next queued job (there must be one).
  JobSpec next();
  // The job runs now in process `pid` on `host`.
  void started(const JobSpec& spec, const std::string& host, long pid);
  void stage(const std::string& fabric_id, const std::string& stage);
  // The job ended: its results read from its folder and recorded with the outcome.
  void finished(const std::string& fabric_id, const JobOutcome& outcome);
  // The batch stops before the job ended (SIGINT/SIGTERM): back to queued for the next run.
  void interrupted(const std::string& fabric_id);
  // Heartbeats of the running jobs, at most every heartbeat_interval; and the progress
  // callback, at most once a second or when `force`.
  void tick(bool force = false);

  // The summary at the end (counts from the ledger).
  BatchSummary summary(bool was_interrupted);

 private:
  struct Running {
    JobSpec spec;
    std::string stage;
    std::chrono::steady_clock::time_point start;
  };
  void plan();
  void plan_fabric(const std::string& key, const db::FabricLoad& load, const pipeline::PipelineOptions& fit,
                   bool report, bool own_options);

  BatchOptions m_options;
  std::unique_ptr<DirectoryLock> m_lock;
  Ledger m_ledger;
  BatchSummary m_summary;  // the planning's counts
  std::vector<std::string> m_selected;
  std::deque<JobSpec> m_queue;
  std::map<std::string, Running> m_running;
  std::vector<double> m_job_seconds;  // of the jobs finished in this run
  std::chrono::steady_clock::time_point m_start, m_last_heartbeat, m_last_progress;
};

// True when process `pid` exists on this host.
[[nodiscard]] bool process_alive(long pid);

}  // namespace yarnfit::batch
