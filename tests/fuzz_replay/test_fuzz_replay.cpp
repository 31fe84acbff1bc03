// Every input a fuzz target found a crash with (tests/fuzz_regressions/TARGET/NAME, kept as
// found) replayed through the target's own code (fuzz/fuzz_TARGET.cpp, built here without
// libFuzzer): the reader must now answer it as its contract says (a problem list, or the
// exception it documents), and the target's own checks must hold. docs/reliability.md.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_support.hpp"

namespace fs = std::filesystem;

namespace {

fs::path regressions() { return fs::path(YARNFIT_SOURCE_DIR) / "tests/fuzz_regressions"; }

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FuzzReplay, EveryTargetIsRegistered) {
  // The targets fuzz/CMakeLists.txt builds; one missing here would replay nothing.
  for (const char* name : {"fabric_record", "tensile_import", "pyp_tile", "tile_charts", "yarn_params",
                           "uniform_targets", "shell_fit_file", "yarn_fit_file", "tile_file", "fit_checkpoint",
                           "swarm_checkpoint", "fit_request", "archive_upload", "fab_physics"})
    EXPECT_TRUE(yarnfit::fuzz::replay_targets().contains(name)) << name;
}

TEST(FuzzReplay, EveryKeptFindingIsAnsweredAsTheReaderPromises) {
  int replayed = 0;
  for (const auto& folder : fs::directory_iterator(regressions())) {
    const std::string target = folder.path().filename().string();
    const auto found = yarnfit::fuzz::replay_targets().find(target);
    ASSERT_NE(found, yarnfit::fuzz::replay_targets().end()) << "no fuzz target named " << target;
    for (const auto& input : fs::directory_iterator(folder.path())) {
      const std::string bytes = bytes_of(input.path());
      EXPECT_NO_THROW(found->second(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()))
          << target << "/" << input.path().filename().string();
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 0);
  std::cout << "[ replayed ] " << replayed << " kept inputs\n";
}

}  // namespace
