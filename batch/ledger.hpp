#pragma once
// The batch ledger: DIR/batch.db, an SQLite database in WAL mode with one writer (the batch
// process, or rank 0 under MPI). Its schema is an interface (SPEC §5, docs/batch.md) and is
// kept stable like the JSON names: columns are added, never renamed or removed.
//
//   jobs     one row per fabric: fabric_id, family, folder, hash (SHA-256 over the record's
//            files, its tile and the fit options), options (JSON), status queued | running |
//            done | failed, stage (while running), attempts, host, pid, heartbeat, started,
//            ended (Unix seconds), error
//   results  one row per fabric and stage ('shell', 'yarn'): family, converged, every SPEC
//            error metric (stretch_force_pct, compression_pct, bending_pct,
//            stress_comfort_pct, stress_full_pct), every fitted parameter, evaluations,
//            seconds; `params` holds the stage's params object as JSON
//   events   what happened, in order: queued, changed, started, taken_over, done, failed,
//            invalid, interrupted, deleted — an audit trail (a fabric finished twice would show two
//            `done` events for one hash)
//   meta     schema_version, created_by
//
// Every change is one transaction: a reader (`sqlite3 DIR/batch.db`, `batch status`) sees a
// job and its results change together or not at all.

#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "numerics/util/error.hpp"

struct sqlite3;

namespace yarnfit::batch {

inline constexpr int k_ledger_schema_version = 1;

struct JobRow {
  std::string fabric_id;
  std::string family;
  std::string folder;
  std::string hash;
  std::string options;  // JSON
  std::string status;   // queued, running, done, failed
  std::string stage;    // while running
  int attempts = 0;
  std::string host;
  long pid = 0;
  double heartbeat = 0.0;
  double started = 0.0;
  double ended = 0.0;
  std::string error;
};

// One row of `results`. `values` follows result_columns(); NaN is stored as NULL.
struct ResultRow {
  std::string fabric_id;
  std::string stage;  // shell, yarn
  std::string family;
  std::vector<double> values;
  std::string params;  // JSON object
};

// The numeric columns of `results`, in table order (after fabric_id, stage, family).
[[nodiscard]] const std::vector<std::string>& result_columns();

struct EventRow {
  double time = 0.0;
  std::string fabric_id;
  std::string event;
  std::string host;
  long pid = 0;
  std::string detail;
};

class Ledger {
 public:
  // Opens or creates the ledger (and its schema). Throws an Error naming the file.
  explicit Ledger(const std::filesystem::path& file);
  // Opens an existing ledger read-only (batch status); throws when there is none.
  static Ledger open_read_only(const std::filesystem::path& file);
  ~Ledger();
  Ledger(Ledger&& other) noexcept;
  Ledger& operator=(Ledger&&) = delete;
  Ledger(const Ledger&) = delete;
  Ledger& operator=(const Ledger&) = delete;

  [[nodiscard]] const std::filesystem::path& file() const { return m_file; }

  [[nodiscard]] std::optional<JobRow> job(const std::string& fabric_id) const;
  [[nodiscard]] std::vector<JobRow> jobs() const;
  [[nodiscard]] std::vector<ResultRow> results() const;
  [[nodiscard]] std::vector<EventRow> events() const;

  // Inserts or replaces the job as given, and logs `event` (with `detail`) for it.
  void put_job(const JobRow& job, std::string_view event, std::string_view detail, double now);
  // queued → running: attempts + 1, host, pid, started = heartbeat = now, no error.
  void start_job(const std::string& fabric_id, const std::string& host, long pid, double now);
  void heartbeat(const std::vector<std::string>& fabric_ids, double now);
  void set_stage(const std::string& fabric_id, const std::string& stage, double now);
  // running → done or failed, with the rows of the outputs written (they replace the
  // fabric's earlier results); `error` empty when done.
  void finish_job(const std::string& fabric_id, bool done, const std::string& error,
                  const std::vector<ResultRow>& rows, double now);
  // running → queued (the batch was interrupted; the next run resumes it).
  void requeue(const std::string& fabric_id, const std::string& why, double now);
  // Removes a job that has ended (done or failed) and its results, logging `deleted` with
  // `why`; false (and nothing changed) when the job is queued or running. Its events stay.
  bool forget_job(const std::string& fabric_id, const std::string& why, double now);

 private:
  Ledger(const std::filesystem::path& file, bool read_only);
  void exec(const std::string& sql) const;
  // Runs `body` in one IMMEDIATE transaction, rolled back when it throws.
  void transaction(const std::function<void()>& body);
  void log_event(const std::string& fabric_id, std::string_view event, std::string_view detail,
                 const std::string& host, long pid, double now);

  std::filesystem::path m_file;
  sqlite3* m_db = nullptr;
};

// Unix time [s].
[[nodiscard]] double unix_now();
[[nodiscard]] std::string host_name();

}  // namespace yarnfit::batch
