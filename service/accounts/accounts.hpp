#pragma once
// The service's users and their API tokens (issue 35: `yarnfit serve user add NAME [--admin]
// DATA_DIR`), in DATA_DIR/accounts.db (SQLite).
//
// A token is "yft_<id>_<secret>": <id> (16 hex digits) finds the user's row, <secret> is 256
// bits from the system's CSPRNG (OpenSSL's RAND_bytes) in base64url. Only the SHA-256 of the
// secret is stored; a presented token's is compared with it in constant time (CRYPTO_memcmp).
// The token is shown once, when it is issued: nothing can show it again. Revoking a user
// refuses their token from then on; a new token replaces the old one.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "numerics/util/error.hpp"

struct sqlite3;

namespace yarnfit::service {

struct Account {
  std::string name;
  bool admin = false;
  bool revoked = false;
  double created = 0.0;  // Unix seconds
};

// An account with the token just issued for it: the only time the token exists in clear.
struct IssuedToken {
  Account account;
  std::string token;
};

// Why a user name cannot be used ("" when it can): 1 to 64 of a-z, 0-9, '.', '_', '-',
// starting with a letter or digit.
[[nodiscard]] std::string user_name_problem(std::string_view name);

class Accounts {
 public:
  // Opens DATA_DIR/accounts.db, creating it (and its table) when absent.
  explicit Accounts(const std::filesystem::path& file);
  ~Accounts();
  Accounts(const Accounts&) = delete;
  Accounts& operator=(const Accounts&) = delete;

  // A new user and their first token. Throws an Error for a bad or taken name.
  IssuedToken add_user(const std::string& name, bool admin);
  // A new token for the user (the old one stops working); clears a revocation. Throws
  // an Error for an unknown user.
  IssuedToken new_token(const std::string& name);
  // The user's token stops working. Throws an Error for an unknown user.
  void revoke(const std::string& name);

  // The account a bearer token belongs to; none for a malformed, unknown or revoked token.
  [[nodiscard]] std::optional<Account> authenticate(std::string_view token) const;
  [[nodiscard]] std::optional<Account> find(const std::string& name) const;
  [[nodiscard]] std::vector<Account> list() const;

 private:
  IssuedToken issue(const std::string& name);
  std::filesystem::path m_file;
  sqlite3* m_db = nullptr;
};

}  // namespace yarnfit::service
