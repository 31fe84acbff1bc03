#pragma once
// `yarnfit batch` as a library (SPEC §5, §5a): every fabric of a database through the
// pipeline, resumable, nothing lost.
//
//   batch::BatchOptions options;
//   options.database = "fabrics";  options.out = "runs/2026-12";  options.jobs = 2;
//   const batch::BatchSummary s = batch::run_batch(options);   // or run_batch_mpi under mpirun
//   return s.exit_code();                                     // 0 all done, 1 some failed
//
// How a run decides what to do, fabric by fabric (the ledger DIR/batch.db, batch/ledger.hpp):
//   - the record is invalid (any problem of `db validate`, or one the pipeline would refuse):
//     recorded as failed with every problem, not run;
//   - no job yet, or its hash changed (the record, a file it names, its tile or the options):
//     queued afresh, its old files and checkpoint removed;
//   - done with the same hash: skipped; failed with the same hash: skipped unless
//     retry_failed (then resumed from its checkpoint);
//   - running, but the batch that ran it is gone (on this host: the lock is free, so it is;
//     elsewhere: its heartbeat is older than stale_after): taken over and resumed inside its
//     swarm from the checkpoint; running with a live heartbeat on another host (a shared
//     DIR whose lock that host does not see): left alone and reported;
//   - queued (an earlier run stopped before it): run, resumed if it has a checkpoint.
// One batch at a time per DIR: DIR/batch.lock is held for the whole run.

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "batch/batch_options.hpp"
#include "batch/ledger.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::batch {

struct FailedFabric {
  std::string fabric_id;
  std::string error;
};

struct BatchSummary {
  int selected = 0;        // fabrics of the database this run is about (after --family, --only)
  int done = 0;            // done at the end (including those skipped as already done)
  int failed = 0;          // failed at the end (including invalid records)
  int ran = 0;             // jobs this run started
  int skipped_done = 0;    // done earlier with the same hash
  int skipped_failed = 0;  // failed earlier with the same hash, not retried
  int taken_over = 0;      // found running with a dead process, resumed
  int invalid = 0;         // records with problems, not run
  std::vector<FailedFabric> failures;          // every failed fabric, with its reason
  std::vector<std::string> running_elsewhere;  // held by a live process elsewhere
  bool interrupted = false;                    // stopped by SIGINT/SIGTERM; rerun to continue
  double seconds = 0.0;
  bool coordinator = true;  // false on MPI worker ranks (nothing to report)

  // 0 when every selected fabric is done, else 1.
  [[nodiscard]] int exit_code() const { return done == selected && !interrupted ? 0 : 1; }
};

// Runs the batch on this machine: `jobs` fabrics at once, each in a child process (a crash in
// one fit cannot take the batch down) with `threads_per_job` OpenMP threads. Throws
// an Error when nothing can be run (see above); a failing fabric never throws.
BatchSummary run_batch(const BatchOptions& options);

// True when this yarnfit was built with MPI.
[[nodiscard]] bool mpi_available();
// The same batch on MPI ranks (every rank calls it; it initialises and finalises MPI unless
// the caller did): rank 0
// owns the ledger and hands fabrics to ranks 1…K−1, which fit them in-process with
// `threads_per_job` threads each and write into DIR (a shared filesystem). Rank 0 returns
// the summary, the workers one with coordinator = false once rank 0 has no more work. Throws an Error
// (on rank 0, after telling the workers to stop) as run_batch does, and when built without MPI.
BatchSummary run_batch_mpi(const BatchOptions& options);

// MPI for a caller that runs more than the batch under mpirun (the service: rank 0 serves HTTP
// and coordinates, the others fit): initialised (threads SERIALIZED: the batch may run on a
// thread other than the main one) from construction to destruction, on the main thread.
// Throws an Error when built without MPI.
class MpiScope {
 public:
  MpiScope();
  ~MpiScope();
  MpiScope(const MpiScope&) = delete;
  MpiScope& operator=(const MpiScope&) = delete;
  [[nodiscard]] int rank() const { return m_rank; }
  [[nodiscard]] int size() const { return m_size; }
  // Ends every rank (rank 0 failed before the others could be told to stop).
  [[noreturn]] void abort(int code);

 private:
  int m_rank = 0, m_size = 1;
};

// The ledger as `batch status --json` prints it: {"ledger", "counts" {queued, running, done,
// failed}, "jobs" [...], "results" [...]}.
[[nodiscard]] nlohmann::json batch_status_json(const Ledger& ledger);

}  // namespace yarnfit::batch
