// examples/fit_through_library.cpp fits the bundled example through the library (about 20 s):
// it ends with exit 0, prints the shell and yarn errors, and writes the folder `yarnfit fit`
// writes, whose shell results are the ones it printed.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <regex>
#include <string>

#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

TEST(LibraryExample, FitsTheBundledExampleAndPrintsItsErrors) {
  ScratchDir dir("library_example");
  const std::string cmd = quoted(YARNFIT_LIBRARY_EXAMPLE) + " " +
                          quoted(fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo") + " " +
                          quoted(dir / "out") + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  const int status = ::pclose(pipe);
  ASSERT_EQ(status, 0) << out;
  const std::regex shell("shell errors: force ([0-9.e+-]+) %, compression [0-9.e+-]+ %, aspect ratio [0-9.e+-]+ %");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, shell)) << out;
  for (const char* d : {"weft", "bias", "warp"})
    EXPECT_NE(out.find(std::string("yarn errors (") + d + "): stress comfort "), std::string::npos) << out;
  EXPECT_NE(out.find("wrote 7 files"), std::string::npos) << out;
  // The example's curves come from a yarn model's homogenised law: the shell fit reproduces them
  // to a few percent (README: force 2.1 %).
  EXPECT_LT(std::stod(m[1]), 5.0) << out;
  const auto j = nlohmann::json::parse(read_file(dir / "out" / "shell_fit.json"));
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_NEAR(j["errors"]["stretch_force_pct"].get<double>(), std::stod(m[1]), 1e-2 * std::stod(m[1]));
  EXPECT_TRUE(fs::exists(dir / "out" / "summary.txt"));
}

}  // namespace
}  // namespace yarnfit::testing
