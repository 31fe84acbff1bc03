// `yarnfit serve user …` (cli/commands_serve.cpp): a token is printed once and works, the list
// never shows one, and bad names, taken names and unknown users are refused with exit 2.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "tests/test_support.hpp"

#include "service/accounts/accounts.hpp"

namespace yarnfit::service {
namespace {

using namespace yarnfit::testing;

TEST(ServeUserCli, AddPrintsATokenOnceThatTheServiceAccepts) {
  ScratchDir dir("serve_user");
  const std::string data = quoted(dir / "data");
  const auto added = run_cli("serve user add ana " + data);
  ASSERT_EQ(added.exit_code, 0) << added.err;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(added.out, m, std::regex("token: (yft_[0-9a-f]{16}_[A-Za-z0-9_-]{43})\n"))) << added.out;
  const std::string token = m[1];
  EXPECT_EQ(Accounts(dir / "data" / "accounts.db").authenticate(token)->name, "ana");

  EXPECT_EQ(run_cli("serve user add ana " + data).exit_code, 2);
  EXPECT_EQ(run_cli("serve user add 'Bad Name' " + data).exit_code, 2);
  EXPECT_EQ(run_cli("serve user revoke bob " + data).exit_code, 2);
  ASSERT_EQ(run_cli("serve user add lab --admin " + data).exit_code, 0);
  const auto list = run_cli("serve user list " + data);
  EXPECT_EQ(list.out, "ana\nlab  admin\n");
  EXPECT_EQ(list.out.find("yft_"), std::string::npos);

  ASSERT_EQ(run_cli("serve user revoke ana " + data).exit_code, 0);
  EXPECT_FALSE(Accounts(dir / "data" / "accounts.db").authenticate(token));
  const auto again = run_cli("serve user token ana " + data);
  ASSERT_EQ(again.exit_code, 0);
  ASSERT_TRUE(std::regex_search(again.out, m, std::regex("token: (yft_\\S+)\n")));
  EXPECT_TRUE(Accounts(dir / "data" / "accounts.db").authenticate(m[1].str()));
}

}  // namespace
}  // namespace yarnfit::service
