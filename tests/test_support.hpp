#pragma once
// Helpers shared by the test executables: scratch folders, files, the shared data and
// running the yarnfit command line.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace yarnfit::testing {

namespace fs = std::filesystem;

// A fresh folder under the system temp dir, removed when the object goes out of scope.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag);
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return m_path; }
  [[nodiscard]] fs::path operator/(const std::string& rel) const { return m_path / rel; }

 private:
  fs::path m_path;
};

void write_file(const fs::path& file, const std::string& text);
std::string read_file(const fs::path& file);

// ../shared next to the source tree (or $YARNFIT_SHARED_DIR).
fs::path shared_dir();
// A HYLC tile of ../shared/data/patterns, and the stockinette most tests run on.
fs::path shared_pattern(const std::string& name);
inline fs::path shared_stockinette() { return shared_pattern("stockinette.pyp"); }
// True when CI=true is set: missing shared data is then a failure, not a skip.
bool running_in_ci();

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Runs the built `yarnfit` with `args` (already shell-quoted where needed).
CommandResult run_cli(const std::string& args);
// Quotes a path for the shell.
std::string quoted(const fs::path& p);
// The factor on the tests' own waits for a fit, as on their CTest timeouts
// (YARNFIT_TEST_TIMEOUT_SCALE: a sanitised fit runs ten times slower).
#ifndef YARNFIT_TEST_TIMEOUT_SCALE
#define YARNFIT_TEST_TIMEOUT_SCALE 1
#endif
inline constexpr double k_wait_scale = YARNFIT_TEST_TIMEOUT_SCALE;
// True when `part` occurs in `text` (for EXPECT_TRUE(contains(report, "line\n")) << report).
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace yarnfit::testing

// Skips the test when `path` is missing, or fails it under CI (SPEC §6).
#define YARNFIT_REQUIRE_SHARED(path)                                                      \
  do {                                                                                   \
    if (!std::filesystem::exists(path)) {                                                \
      if (::yarnfit::testing::running_in_ci()) {                                         \
        FAIL() << "shared data missing: " << (path)                                      \
               << " (CI=true: tests need ../shared/data beside the repository)";         \
      } else {                                                                           \
        GTEST_SKIP() << "shared data missing: " << (path);                               \
      }                                                                                  \
    }                                                                                    \
  } while (0)
