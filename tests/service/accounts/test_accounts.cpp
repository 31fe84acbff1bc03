// The service's users and tokens (service/accounts/accounts.hpp): a token works until revoked or
// replaced, a changed character or another user's id does not, the database never holds a token
// or its secret in clear, and all of it survives reopening the file.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

#include "tests/test_support.hpp"

#include "fabrics_db/records/sha256.hpp"
#include "service/accounts/accounts.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::service {
namespace {

using namespace yarnfit::testing;

const std::regex k_token_form("yft_[0-9a-f]{16}_[A-Za-z0-9_-]{43}");

TEST(Accounts, ATokenWorksUntilRevokedAndOnlyAsIssued) {
  ScratchDir dir("accounts");
  Accounts accounts(dir / "accounts.db");
  const IssuedToken ana = accounts.add_user("ana", false);
  const IssuedToken root = accounts.add_user("lab-admin", true);
  EXPECT_TRUE(std::regex_match(ana.token, k_token_form)) << ana.token;
  EXPECT_NE(ana.token, root.token);
  ASSERT_TRUE(accounts.authenticate(ana.token));
  EXPECT_EQ(accounts.authenticate(ana.token)->name, "ana");
  EXPECT_FALSE(accounts.authenticate(ana.token)->admin);
  EXPECT_TRUE(accounts.authenticate(root.token)->admin);

  // One character changed in the secret, ana's id with the admin's secret, malformed forms.
  std::string changed = ana.token;
  changed.back() = changed.back() == 'A' ? 'B' : 'A';
  EXPECT_FALSE(accounts.authenticate(changed));
  EXPECT_FALSE(accounts.authenticate(ana.token.substr(0, 21) + root.token.substr(21)));
  for (const std::string& bad : {std::string(), std::string("yft_"), ana.token + "x", ana.token.substr(1),
                                "Bearer " + ana.token, std::string(64, 'a')})
    EXPECT_FALSE(accounts.authenticate(bad)) << bad;

  accounts.revoke("ana");
  EXPECT_FALSE(accounts.authenticate(ana.token));
  EXPECT_TRUE(accounts.find("ana")->revoked);
  EXPECT_TRUE(accounts.authenticate(root.token));  // only hers

  // A new token replaces the old one and lifts the revocation.
  const IssuedToken again = accounts.new_token("ana");
  EXPECT_TRUE(accounts.authenticate(again.token));
  EXPECT_FALSE(accounts.authenticate(ana.token));
  EXPECT_FALSE(accounts.find("ana")->revoked);
}

TEST(Accounts, TheDatabaseHoldsOnlyTheSecretsHash) {
  ScratchDir dir("accounts_hash");
  std::string token;
  {
    Accounts accounts(dir / "accounts.db");
    token = accounts.add_user("ana", false).token;
  }
  const std::string secret = token.substr(21);
  std::string bytes = read_file(dir / "accounts.db");
  for (const char* side : {"-wal", "-shm"})
    if (std::filesystem::exists(dir / ("accounts.db" + std::string(side)))) bytes += read_file(dir / ("accounts.db" + std::string(side)));
  EXPECT_EQ(bytes.find(secret), std::string::npos);
  EXPECT_EQ(bytes.find(token), std::string::npos);
  EXPECT_NE(bytes.find(db::sha256_hex(secret)), std::string::npos);
  // Reopened, the token still works.
  Accounts reopened(dir / "accounts.db");
  ASSERT_TRUE(reopened.authenticate(token));
  EXPECT_EQ(reopened.list().size(), 1u);
}

TEST(Accounts, NamesAreCheckedAndTaken) {
  ScratchDir dir("accounts_names");
  Accounts accounts(dir / "accounts.db");
  for (const char* bad : {"", "Ana", "-x", "a b", "../x", "a/b", "é"})
    EXPECT_ERROR(accounts.add_user(bad, false), yarnfit::ErrorCategory::input) << bad;
  EXPECT_ERROR(accounts.add_user(std::string(65, 'a'), false), yarnfit::ErrorCategory::input);
  accounts.add_user("ana", false);
  EXPECT_ERROR(accounts.add_user("ana", true), yarnfit::ErrorCategory::conflict);
  EXPECT_FALSE(accounts.find("ana")->admin);  // the refused second add changed nothing
  EXPECT_ERROR(accounts.revoke("bob"), yarnfit::ErrorCategory::input);
  EXPECT_ERROR(accounts.new_token("bob"), yarnfit::ErrorCategory::input);
  accounts.add_user("bob.lab_2", true);
  const auto all = accounts.list();
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].name, "ana");
  EXPECT_EQ(all[1].name, "bob.lab_2");
}

TEST(Accounts, TokensAreDrawnFreshEachTime) {
  ScratchDir dir("accounts_random");
  Accounts accounts(dir / "accounts.db");
  std::set<std::string> tokens;
  accounts.add_user("ana", false);
  for (int i = 0; i < 50; ++i) tokens.insert(accounts.new_token("ana").token);
  EXPECT_EQ(tokens.size(), 50u);
}

}  // namespace
}  // namespace yarnfit::service
