#include "batch/ledger.hpp"

#include "batch/sqlite_statement.hpp"
#include "numerics/util/error.hpp"

#include <sqlite3.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>

namespace yarnfit::batch {

namespace {

// The schema of version 1. CREATE … IF NOT EXISTS: opening an existing ledger changes nothing.
constexpr const char* k_schema = R"sql(
CREATE TABLE IF NOT EXISTS meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS jobs(
  fabric_id TEXT PRIMARY KEY,
  family TEXT NOT NULL DEFAULT '',
  folder TEXT NOT NULL,
  hash TEXT NOT NULL,
  options TEXT NOT NULL,
  status TEXT NOT NULL CHECK(status IN ('queued', 'running', 'done', 'failed')),
  stage TEXT,
  attempts INTEGER NOT NULL DEFAULT 0,
  host TEXT,
  pid INTEGER,
  heartbeat REAL,
  started REAL,
  ended REAL,
  error TEXT);
CREATE TABLE IF NOT EXISTS results(
  fabric_id TEXT NOT NULL,
  stage TEXT NOT NULL CHECK(stage IN ('shell', 'yarn')),
  family TEXT NOT NULL DEFAULT '',
  converged INTEGER,
  stretch_force_pct REAL, compression_pct REAL, bending_pct REAL,
  stress_comfort_pct REAL, stress_full_pct REAL,
  kxx REAL, kxy REAL, kyy REAL, kss REAL, kn1 REAL, kn2 REAL,
  ktheta_weft REAL, ktheta_bias REAL, ktheta_warp REAL,
  ks1 REAL, eps_s REAL, kb REAL, R1 REAL, kc1 REAL, ks2 REAL, kc2 REAL, R2 REAL,
  evaluations INTEGER,
  seconds REAL,
  params TEXT,
  PRIMARY KEY(fabric_id, stage));
CREATE TABLE IF NOT EXISTS events(
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  time REAL NOT NULL,
  fabric_id TEXT NOT NULL,
  event TEXT NOT NULL,
  host TEXT,
  pid INTEGER,
  detail TEXT);
)sql";

// A prepared statement; every failure throws an io Error naming the ledger file.
using Statement = SqliteStatement;

constexpr const char* k_job_columns =
    "fabric_id, family, folder, hash, options, status, stage, attempts, host, pid, heartbeat, started, ended, error";

JobRow job_from(const Statement& s) {
  JobRow j;
  j.fabric_id = s.text(0);
  j.family = s.text(1);
  j.folder = s.text(2);
  j.hash = s.text(3);
  j.options = s.text(4);
  j.status = s.text(5);
  j.stage = s.text(6);
  j.attempts = static_cast<int>(s.integer(7));
  j.host = s.text(8);
  j.pid = s.integer(9);
  j.heartbeat = s.real(10);
  j.started = s.real(11);
  j.ended = s.real(12);
  j.error = s.text(13);
  return j;
}

}  // namespace

const std::vector<std::string>& result_columns() {
  static const std::vector<std::string> columns{
      "converged",   "stretch_force_pct", "compression_pct", "bending_pct", "stress_comfort_pct", "stress_full_pct",
      "kxx",         "kxy",               "kyy",             "kss",         "kn1",                "kn2",
      "ktheta_weft", "ktheta_bias",       "ktheta_warp",     "ks1",         "eps_s",              "kb",
      "R1",          "kc1",               "ks2",             "kc2",         "R2",                 "evaluations",
      "seconds"};
  return columns;
}

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

Ledger::Ledger(const std::filesystem::path& file) : Ledger(file, false) {}

Ledger Ledger::open_read_only(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file)) throw Error(ErrorCategory::input, file.string() + ": no batch ledger here");
  return Ledger(file, true);
}

Ledger::Ledger(const std::filesystem::path& file, bool read_only) : m_file(file) {
  // Readers (status, sqlite3) wait for the writer's short transactions instead of failing.
  m_db = open_sqlite(file, read_only, "the batch ledger");
  if (read_only) return;
  // WAL: readers never block the writer; synchronous=FULL: a committed job survives a power cut.
  exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;");
  exec(std::string("BEGIN IMMEDIATE;") + k_schema + "COMMIT;");
  Statement version(m_db, m_file, "SELECT value FROM meta WHERE key = 'schema_version'");
  if (version.step()) {
    if (version.text(0) != std::to_string(k_ledger_schema_version))
      throw Error(ErrorCategory::conflict, file.string() + ": ledger schema version " + version.text(0) +
                                               ", this yarnfit writes " + std::to_string(k_ledger_schema_version));
  } else {
    Statement put(m_db, m_file, "INSERT INTO meta(key, value) VALUES ('schema_version', ?1), ('created_by', ?2)");
    put.bind(1, std::to_string(k_ledger_schema_version)).bind(2, std::string("yarnfit batch")).run();
  }
}

Ledger::~Ledger() {
  if (m_db) sqlite3_close(m_db);
}

Ledger::Ledger(Ledger&& other) noexcept : m_file(std::move(other.m_file)), m_db(std::exchange(other.m_db, nullptr)) {}

void Ledger::exec(const std::string& sql) const { exec_sql(m_db, m_file, sql); }

void Ledger::transaction(const std::function<void()>& body) { sql_transaction(m_db, m_file, body); }

std::optional<JobRow> Ledger::job(const std::string& fabric_id) const {
  Statement s(m_db, m_file, std::string("SELECT ") + k_job_columns + " FROM jobs WHERE fabric_id = ?1");
  s.bind(1, fabric_id);
  if (!s.step()) return std::nullopt;
  return job_from(s);
}

std::vector<JobRow> Ledger::jobs() const {
  Statement s(m_db, m_file, std::string("SELECT ") + k_job_columns + " FROM jobs ORDER BY fabric_id");
  std::vector<JobRow> out;
  while (s.step()) out.push_back(job_from(s));
  return out;
}

std::vector<ResultRow> Ledger::results() const {
  std::string sql = "SELECT fabric_id, stage, family, params";
  for (const auto& c : result_columns()) sql += ", " + c;
  Statement s(m_db, m_file, sql + " FROM results ORDER BY fabric_id, stage");
  std::vector<ResultRow> out;
  while (s.step()) {
    ResultRow r{s.text(0), s.text(1), s.text(2), {}, s.text(3)};
    for (std::size_t i = 0; i < result_columns().size(); ++i) r.values.push_back(s.real(static_cast<int>(i) + 4));
    out.push_back(std::move(r));
  }
  return out;
}

std::vector<EventRow> Ledger::events() const {
  Statement s(m_db, m_file, "SELECT time, fabric_id, event, host, pid, detail FROM events ORDER BY id");
  std::vector<EventRow> out;
  while (s.step()) out.push_back({s.real(0), s.text(1), s.text(2), s.text(3), s.integer(4), s.text(5)});
  return out;
}

void Ledger::log_event(const std::string& fabric_id, std::string_view event, std::string_view detail,
                       const std::string& host, long pid, double now) {
  Statement s(m_db, m_file, "INSERT INTO events(time, fabric_id, event, host, pid, detail) VALUES (?1, ?2, ?3, ?4, ?5, ?6)");
  s.bind(1, now).bind(2, fabric_id).bind(3, std::string(event)).bind(4, host).bind(5, pid).bind(6, std::string(detail));
  s.run();
}

void Ledger::put_job(const JobRow& j, std::string_view event, std::string_view detail, double now) {
  transaction([&] {
    Statement s(m_db, m_file,
                std::string("INSERT OR REPLACE INTO jobs(") + k_job_columns +
                    ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)");
    s.bind(1, j.fabric_id).bind(2, j.family).bind(3, j.folder).bind(4, j.hash).bind(5, j.options).bind(6, j.status);
    s.bind(7, j.stage).bind(8, static_cast<long>(j.attempts)).bind(9, j.host).bind(10, j.pid);
    s.bind(11, j.heartbeat).bind(12, j.started).bind(13, j.ended).bind(14, j.error);
    s.run();
    log_event(j.fabric_id, event, detail, host_name(), static_cast<long>(getpid()), now);
  });
}

void Ledger::start_job(const std::string& fabric_id, const std::string& host, long pid, double now) {
  transaction([&] {
    Statement s(m_db, m_file,
                "UPDATE jobs SET status = 'running', stage = 'starting', attempts = attempts + 1, host = ?2, pid = ?3, "
                "heartbeat = ?4, started = ?4, ended = NULL, error = NULL WHERE fabric_id = ?1");
    s.bind(1, fabric_id).bind(2, host).bind(3, pid).bind(4, now).run();
    log_event(fabric_id, "started", "", host, pid, now);
  });
}

void Ledger::heartbeat(const std::vector<std::string>& fabric_ids, double now) {
  if (fabric_ids.empty()) return;
  transaction([&] {
    for (const auto& id : fabric_ids) {
      Statement s(m_db, m_file, "UPDATE jobs SET heartbeat = ?2 WHERE fabric_id = ?1 AND status = 'running'");
      s.bind(1, id).bind(2, now).run();
    }
  });
}

void Ledger::set_stage(const std::string& fabric_id, const std::string& stage, double now) {
  Statement s(m_db, m_file, "UPDATE jobs SET stage = ?2, heartbeat = ?3 WHERE fabric_id = ?1 AND status = 'running'");
  s.bind(1, fabric_id).bind(2, stage).bind(3, now).run();
}

void Ledger::finish_job(const std::string& fabric_id, bool done, const std::string& error,
                        const std::vector<ResultRow>& rows, double now) {
  transaction([&] {
    Statement s(m_db, m_file,
                "UPDATE jobs SET status = ?2, stage = NULL, ended = ?3, heartbeat = ?3, error = ?4 WHERE fabric_id = ?1");
    s.bind(1, fabric_id).bind(2, std::string(done ? "done" : "failed")).bind(3, now);
    if (error.empty()) s.bind_null(4);
    else s.bind(4, error);
    s.run();
    Statement clear(m_db, m_file, "DELETE FROM results WHERE fabric_id = ?1");
    clear.bind(1, fabric_id).run();
    std::string sql = "INSERT INTO results(fabric_id, stage, family, params";
    std::string values = "?1, ?2, ?3, ?4";
    for (std::size_t i = 0; i < result_columns().size(); ++i) {
      sql += ", " + result_columns()[i];
      values += ", ?" + std::to_string(i + 5);
    }
    for (const auto& r : rows) {
      Statement put(m_db, m_file, sql + ") VALUES (" + values + ")");
      put.bind(1, r.fabric_id).bind(2, r.stage).bind(3, r.family).bind(4, r.params);
      for (std::size_t i = 0; i < result_columns().size(); ++i) {
        const double v = i < r.values.size() ? r.values[i] : std::numeric_limits<double>::quiet_NaN();
        put.bind(static_cast<int>(i) + 5, v);
      }
      put.run();
    }
    const auto job = this->job(fabric_id);
    log_event(fabric_id, done ? "done" : "failed", done ? (job ? job->hash : "") : error, job ? job->host : "",
              job ? job->pid : 0, now);
  });
}

void Ledger::requeue(const std::string& fabric_id, const std::string& why, double now) {
  transaction([&] {
    Statement s(m_db, m_file, "UPDATE jobs SET status = 'queued', stage = NULL WHERE fabric_id = ?1 AND status = 'running'");
    s.bind(1, fabric_id).run();
    log_event(fabric_id, "interrupted", why, host_name(), static_cast<long>(getpid()), now);
  });
}

bool Ledger::forget_job(const std::string& fabric_id, const std::string& why, double now) {
  bool forgot = false;
  transaction([&] {
    Statement active(m_db, m_file, "SELECT 1 FROM jobs WHERE fabric_id = ?1 AND status IN ('queued', 'running')");
    if (active.bind(1, fabric_id).step()) return;
    Statement results(m_db, m_file, "DELETE FROM results WHERE fabric_id = ?1");
    results.bind(1, fabric_id).run();
    Statement jobs(m_db, m_file, "DELETE FROM jobs WHERE fabric_id = ?1");
    jobs.bind(1, fabric_id).run();
    log_event(fabric_id, "deleted", why, host_name(), static_cast<long>(getpid()), now);
    forgot = true;
  });
  return forgot;
}

}  // namespace yarnfit::batch
