#include "service/accounts/accounts.hpp"

#include <openssl/crypto.h>
#include <openssl/err.h>
#include <openssl/rand.h>

#include <array>
#include <chrono>

#include "fabrics_db/records/sha256.hpp"
#include "batch/sqlite_statement.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::service {

namespace {

using Statement = batch::SqliteStatement;

constexpr const char* k_schema = R"sql(
CREATE TABLE IF NOT EXISTS users(
  name TEXT PRIMARY KEY,
  admin INTEGER NOT NULL DEFAULT 0,
  token_id TEXT NOT NULL UNIQUE,
  secret_sha256 TEXT NOT NULL,
  revoked INTEGER NOT NULL DEFAULT 0,
  created REAL NOT NULL
);
)sql";

constexpr std::string_view k_prefix = "yft_";

// `n` bytes from the system's CSPRNG.
std::string random_bytes(std::size_t n) {
  std::string out(n, '\0');
  if (RAND_bytes(reinterpret_cast<unsigned char*>(out.data()), static_cast<int>(n)) != 1) {
    const char* why = ERR_reason_error_string(ERR_get_error());
    throw Error(ErrorCategory::system,
                std::string("cannot draw random bytes: ") + (why ? why : "the random generator failed"));
  }
  return out;
}

std::string hex(std::string_view bytes) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string out;
  for (const unsigned char c : bytes) out += {digits[c >> 4], digits[c & 15]};
  return out;
}

// base64url without padding (RFC 4648 §5): the secret as it travels in a header.
std::string base64url(std::string_view bytes) {
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";
  std::string out;
  std::uint32_t buffer = 0;
  int bits = 0;
  for (const unsigned char c : bytes) {
    buffer = (buffer << 8) | c;
    bits += 8;
    while (bits >= 6) {
      bits -= 6;
      out += alphabet[(buffer >> bits) & 63];
    }
  }
  if (bits > 0) out += alphabet[(buffer << (6 - bits)) & 63];
  return out;
}

double now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

Account account_from(const Statement& s) {
  return {s.text(0), s.integer(1) != 0, s.integer(2) != 0, s.real(3)};
}

}  // namespace

std::string user_name_problem(std::string_view name) {
  const auto letter_or_digit = [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'); };
  if (name.empty() || name.size() > 64) return "a user name has 1 to 64 characters";
  if (!letter_or_digit(name.front())) return "a user name starts with a letter a-z or a digit";
  for (const char c : name)
    if (!letter_or_digit(c) && c != '.' && c != '_' && c != '-') return "a user name holds a-z, 0-9, '.', '_' and '-' only";
  return "";
}

Accounts::Accounts(const std::filesystem::path& file) : m_file(file) {
  m_db = batch::open_sqlite(file, false, "the accounts");
  try {
    // Only the service's user reads it (SQLite gives its -wal and -shm files the same mode).
    std::error_code ec;
    std::filesystem::permissions(file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write,
                                 std::filesystem::perm_options::replace, ec);
    batch::exec_sql(m_db, m_file, "PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL;");
    batch::exec_sql(m_db, m_file, std::string("BEGIN IMMEDIATE;") + k_schema + "COMMIT;");
  } catch (...) {
    sqlite3_close(m_db);
    throw;
  }
}

Accounts::~Accounts() { sqlite3_close(m_db); }

IssuedToken Accounts::issue(const std::string& name) {
  const std::string id = hex(random_bytes(8));
  const std::string secret = base64url(random_bytes(32));  // 256 bits
  Statement s(m_db, m_file, "UPDATE users SET token_id = ?1, secret_sha256 = ?2, revoked = 0 WHERE name = ?3");
  s.bind(1, id).bind(2, db::sha256_hex(secret)).bind(3, name).run();
  return {*find(name), std::string(k_prefix) + id + "_" + secret};
}

IssuedToken Accounts::add_user(const std::string& name, bool admin) {
  if (const std::string why = user_name_problem(name); !why.empty()) throw Error(ErrorCategory::input, name + ": " + why);
  IssuedToken issued;
  batch::sql_transaction(m_db, m_file, [&] {
    if (find(name))
      throw Error(ErrorCategory::conflict, name + ": a user of that name exists (revoke or give a new token instead)");
    // A placeholder token id (never a valid one: it holds ':') until issue() draws the real one.
    Statement s(m_db, m_file,
                "INSERT INTO users(name, admin, token_id, secret_sha256, created) VALUES (?1, ?2, ?3, '', ?4)");
    s.bind(1, name).bind(2, long{admin ? 1 : 0}).bind(3, "new:" + name).bind(4, now()).run();
    issued = issue(name);
  });
  return issued;
}

IssuedToken Accounts::new_token(const std::string& name) {
  IssuedToken issued;
  batch::sql_transaction(m_db, m_file, [&] {
    if (!find(name)) throw Error(ErrorCategory::input, name + ": no such user");
    issued = issue(name);
  });
  return issued;
}

void Accounts::revoke(const std::string& name) {
  batch::sql_transaction(m_db, m_file, [&] {
    if (!find(name)) throw Error(ErrorCategory::input, name + ": no such user");
    Statement(m_db, m_file, "UPDATE users SET revoked = 1 WHERE name = ?1").bind(1, name).run();
  });
}

std::optional<Account> Accounts::authenticate(std::string_view token) const {
  // yft_ + 16 hex digits + _ + 43 base64url characters.
  if (token.size() != k_prefix.size() + 16 + 1 + 43 || token.substr(0, k_prefix.size()) != k_prefix ||
      token[k_prefix.size() + 16] != '_')
    return std::nullopt;
  const std::string id(token.substr(k_prefix.size(), 16));
  const std::string presented = db::sha256_hex(token.substr(k_prefix.size() + 17));
  Statement s(m_db, m_file, "SELECT name, admin, revoked, created, secret_sha256 FROM users WHERE token_id = ?1");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  const std::string stored = s.text(4);
  if (stored.size() != presented.size() || CRYPTO_memcmp(stored.data(), presented.data(), stored.size()) != 0)
    return std::nullopt;
  Account a = account_from(s);
  if (a.revoked) return std::nullopt;
  return a;
}

std::optional<Account> Accounts::find(const std::string& name) const {
  Statement s(m_db, m_file, "SELECT name, admin, revoked, created FROM users WHERE name = ?1");
  s.bind(1, name);
  if (!s.step()) return std::nullopt;
  return account_from(s);
}

std::vector<Account> Accounts::list() const {
  Statement s(m_db, m_file, "SELECT name, admin, revoked, created FROM users ORDER BY name");
  std::vector<Account> out;
  while (s.step()) out.push_back(account_from(s));
  return out;
}

}  // namespace yarnfit::service
