// The result files' keys belong to results/: no code that reads or writes them elsewhere names
// one as a string literal. The keys are those results::to_json writes (taken from the files it
// writes, so a key added there is checked at once); the scan covers the modules that write or
// read results (reports/, batch/, cli/, pipeline/, shell_fit/, calibration/) and fails with the
// file, the line and the key.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

#include "results/shell_fit_file.hpp"

namespace yarnfit::results {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using yarnfit::testing::read_file;

// Objects whose keys are data (parameter, direction and scene names), not names of the format.
const std::set<std::string> k_maps = {"params", "start", "bounds", "sensitivity_pct_per_pct_noise", "effects",
                                      "errors_by_direction"};

void collect_keys(const json& j, std::set<std::string>& keys, bool keys_are_data = false) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      if (!keys_are_data) keys.insert(k);
      collect_keys(v, keys, !keys_are_data && k_maps.count(k) > 0);
    }
  } else if (j.is_array()) {
    for (const auto& v : j) collect_keys(v, keys);
  }
}

std::set<std::string> result_keys() {
  const fs::path data = fs::path(YARNFIT_SOURCE_DIR) / "tests/results/data";
  std::set<std::string> keys;
  collect_keys(to_json(shell_fit_file_from_json(json::parse(read_file(data / "shell_fit_v1.json")))), keys);
  return keys;
}

// Keys yarn_fit.json writes too: its readers still take yarn_fit.json by key until it has its
// type in results/ (issue 34's next step), so these cannot be told apart yet.
const std::set<std::string> k_shared_with_yarn_fit = {
    "params", "errors", "bending_pct", "compression_pct", "errors_by_direction", "errors_reason", "curves", "effects",
    "bounds", "lower", "upper", "log", "message", "timing_s", "fabric", "family", "direction", "stretch",
    "simulated_compression", "converged", "iterations", "starts", "start"};
// Ordinary words that name other things all over the code (a scene's direction, a plot's name,
// the model chosen on the command line).
const std::set<std::string> k_words = {"model", "name", "cost", "bending"};

// Where a key may appear as a literal outside results/, and why: the same word naming something
// else that is not read from a result file.
struct Exception {
  const char* file;  // relative to the source root
  const char* key;
  const char* why;
};
const std::vector<Exception> k_exceptions = {
    // The batch ledger's `results` table (SPEC §5: schema documented and kept stable) names its
    // columns after the figures; batch fills them from the types (results::named_errors).
    {"batch/ledger.cpp", "stretch_force_pct", "ledger column"},
    {"batch/ledger.cpp", "compression_pct", "ledger column"},
    {"batch/ledger.cpp", "bending_pct", "ledger column"},
    {"batch/ledger.cpp", "converged", "ledger column"},
    // `batch status` prints the ledger's rows (batch_status_json), not a result file.
    {"cli/commands_batch.cpp", "stretch_force_pct", "ledger column of batch status"},
    {"cli/commands_batch.cpp", "compression_pct", "ledger column of batch status"},
    // `db show` prints a fabric record (its pear-loop clamp distances, whether compression was
    // measured), and `shell sim` / the scenes' JSON name a scene's clamp distance alike.
    {"cli/output.cpp", "clamp_distance_m", "fabric record field"},
    {"cli/output.cpp", "compression_measured", "fabric record field"},
    {"shell_fit/scenes/scene_json.cpp", "clamp_distance_m", "pear-loop scene output of shell sim"},
};

bool excepted(const std::string& file, const std::string& key) {
  for (const auto& e : k_exceptions)
    if (file == e.file && key == e.key) return true;
  return false;
}

TEST(ResultKeys, NoResultKeyIsAStringLiteralOutsideResults) {
  std::set<std::string> keys;
  for (const auto& k : result_keys())
    if (!k_shared_with_yarn_fit.count(k) && !k_words.count(k)) keys.insert(k);
  ASSERT_GT(keys.size(), 20u);
  const fs::path root = YARNFIT_SOURCE_DIR;
  const std::regex literal("\"([A-Za-z_][A-Za-z0-9_]*)\"");
  std::vector<std::string> found;
  for (const char* module : {"reports", "batch", "cli", "pipeline", "shell_fit", "calibration"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / module)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      const std::string rel = fs::relative(entry.path(), root).generic_string();
      std::ifstream in(entry.path());
      std::string line;
      for (int n = 1; std::getline(in, line); ++n) {
        for (std::sregex_iterator m(line.begin(), line.end(), literal), end; m != end; ++m) {
          const std::string key = (*m)[1].str();
          if (keys.count(key) && !excepted(rel, key)) found.push_back(rel + ":" + std::to_string(n) + ": \"" + key + "\"");
        }
      }
    }
  }
  std::string list;
  for (const auto& f : found) list += f + "\n";
  EXPECT_TRUE(found.empty()) << found.size() << " result keys outside results/ (read the types instead):\n" << list;
}

}  // namespace
}  // namespace yarnfit::results
