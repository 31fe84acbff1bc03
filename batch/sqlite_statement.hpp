#pragma once
// A prepared SQLite statement for the project's databases (the batch ledger, the service's
// accounts): binds and reads by column, and every failure throws an `Error` of category io
// naming the database file and what failed.

#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>

#include "numerics/util/error.hpp"

namespace yarnfit::batch {

// Opens (or creates, unless read-only) the database `file`; `what` names it in the error
// ("cannot open the batch ledger: …"). Readers wait up to 10 s for a writer's transaction.
inline sqlite3* open_sqlite(const std::filesystem::path& file, bool read_only, const std::string& what) {
  sqlite3* db = nullptr;
  const int flags = read_only ? SQLITE_OPEN_READONLY : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  if (sqlite3_open_v2(file.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw Error(ErrorCategory::io, file.string() + ": cannot open " + what + ": " + why);
  }
  sqlite3_busy_timeout(db, 10000);
  return db;
}

// Runs `sql` (several statements); whatever transaction a failure leaves open (a failed BEGIN…
// or COMMIT) is rolled back, so the connection does not keep the write lock.
inline void exec_sql(sqlite3* db, const std::filesystem::path& file, const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string why = message ? message : sqlite3_errmsg(db);
    sqlite3_free(message);
    if (!sqlite3_get_autocommit(db)) sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw Error(ErrorCategory::io, file.string() + ": " + why);
  }
}

// `body` in one write transaction: all of it or, when it throws, none of it.
inline void sql_transaction(sqlite3* db, const std::filesystem::path& file, const std::function<void()>& body) {
  exec_sql(db, file, "BEGIN IMMEDIATE");
  try {
    body();
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  exec_sql(db, file, "COMMIT");
}

class SqliteStatement {
 public:
  SqliteStatement(sqlite3* db, const std::filesystem::path& file, const std::string& sql) : m_db(db), m_file(file) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &m_stmt, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~SqliteStatement() { sqlite3_finalize(m_stmt); }
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;

  SqliteStatement& bind(int i, const std::string& text) {
    check(sqlite3_bind_text(m_stmt, i, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT));
    return *this;
  }
  // NaN and ±inf are stored as NULL.
  SqliteStatement& bind(int i, double value) {
    check(std::isfinite(value) ? sqlite3_bind_double(m_stmt, i, value) : sqlite3_bind_null(m_stmt, i));
    return *this;
  }
  SqliteStatement& bind(int i, long value) {
    check(sqlite3_bind_int64(m_stmt, i, value));
    return *this;
  }
  SqliteStatement& bind_null(int i) {
    check(sqlite3_bind_null(m_stmt, i));
    return *this;
  }
  // True while there is a row.
  bool step() {
    const int rc = sqlite3_step(m_stmt);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail("step");
    return false;
  }
  void run() {
    while (step()) {
    }
  }
  [[nodiscard]] std::string text(int col) const {
    const auto* p = sqlite3_column_text(m_stmt, col);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  }
  // NULL reads as NaN.
  [[nodiscard]] double real(int col) const {
    return sqlite3_column_type(m_stmt, col) == SQLITE_NULL ? std::numeric_limits<double>::quiet_NaN()
                                                            : sqlite3_column_double(m_stmt, col);
  }
  [[nodiscard]] long integer(int col) const { return static_cast<long>(sqlite3_column_int64(m_stmt, col)); }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail("bind");
  }
  [[noreturn]] void fail(const char* what) const {
    throw Error(ErrorCategory::io, m_file.string() + ": " + what + ": " + sqlite3_errmsg(m_db));
  }
  sqlite3* m_db;
  std::filesystem::path m_file;
  sqlite3_stmt* m_stmt = nullptr;
};

}  // namespace yarnfit::batch
