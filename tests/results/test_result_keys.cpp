// The result files' keys belong to results/: no code that reads or writes them elsewhere names
// one as a string literal. The keys are those results::to_json writes (taken from the files it
// writes, so a key added there is checked at once); the scan covers the modules that write or
// read results (reports/, batch/, cli/, pipeline/, shell_fit/, yarn_fit/, exports/, service/) and fails with the
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
#include "results/tile_file.hpp"
#include "results/yarn_fit_file.hpp"

namespace yarnfit::results {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace yarnfit::testing;

// Objects whose keys are data (parameter, direction and scene names), not names of the format;
// `settings` holds the fit's options under their own names (the names option validation and the
// command line use, fabrics_db/problems.hpp), not names the result files invented.
const std::set<std::string> k_maps = {"params",  "start",      "bounds", "sensitivity_pct_per_pct_noise",
                                      "effects", "parameters", "errors_by_direction"};
const std::set<std::string> k_option_trees = {"settings"};

void collect_keys(const json& j, std::set<std::string>& keys, bool keys_are_data = false) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      if (!keys_are_data && k_option_trees.count(k)) continue;
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
  collect_keys(to_json(yarn_fit_file_from_json(json::parse(read_file(data / "yarn_fit_v1.json")))), keys);
  collect_keys(to_json(tile_file_from_json(json::parse(read_file(data / "tile_v1.json")))), keys);
  return keys;
}
// Ordinary words that name other things all over the code (a scene's direction, a plot's name,
// the model chosen on the command line, a job's status, a stage of the progress display, the
// fabric a record names, a ledger's seconds): a key this plain cannot be told from them. Every
// key the result files invented (errors_by_direction, measured_force_N, comfort_stretch, …) is
// checked.
const std::set<std::string> k_words = {
    "model",   "name",       "cost",   "bending",  "ok",        "message", "fabric",  "family",   "seconds",
    "failed",  "converged",  "stretch", "start",   "stage",     "stages",  "all",     "swarm",    "local",
    "params",  "iterations", "iteration", "evaluations", "status", "value", "report", "targets", "samples",
    "contact", "runs",       "objective", "total",  "step",      "starts",  "direction", "effects", "free",
    "move",    "round",      "rounds",  "termination", "vertices",  "seed",     "alternation", "global", "method", "history", "best"};

// Where a key may appear as a literal outside results/, and why: the same word naming something
// else that is not read from a result file.
struct Exception {
  const char* file;  // relative to the source root
  const char* key;
  const char* why;
};
const std::vector<Exception> k_exceptions = {
    // U3M 1.1's own field (material.physics.weight, g/m²), required by its schema; filled from
    // the record's areal density, not from a result file.
    {"exports/u3m_material.cpp", "weight", "U3M field"},
    // The batch ledger's `results` table (SPEC §5: schema documented and kept stable) names its
    // columns after the figures; batch fills them from the types (results::named_errors).
    {"batch/ledger.cpp", "stretch_force_pct", "ledger column"},
    {"batch/ledger.cpp", "compression_pct", "ledger column"},
    {"batch/ledger.cpp", "bending_pct", "ledger column"},
    {"batch/ledger.cpp", "stress_comfort_pct", "ledger column"},
    {"batch/ledger.cpp", "stress_full_pct", "ledger column"},
    {"batch/ledger.cpp", "converged", "ledger column"},
    // `batch status` prints the ledger's rows (batch_status_json), not a result file.
    {"cli/commands_batch.cpp", "stretch_force_pct", "ledger column of batch status"},
    {"cli/commands_batch.cpp", "compression_pct", "ledger column of batch status"},
    {"cli/commands_batch.cpp", "stress_comfort_pct", "ledger column of batch status"},
    // report.json's own per-direction columns (reports/collection/report_data.hpp), filled from
    // the types.
    {"reports/collection/report_data.cpp", "compression_pct", "report.json column"},
    // `db show` prints a record's uniform targets (db::DirectionTargets' comfort_stretch).
    {"reports/summaries/fabric_text.cpp", "comfort_stretch", "uniform targets field"},
    // `db show` prints a fabric record (its pear-loop clamp distances, whether compression was
    // measured), and `shell sim` / the scenes' JSON name a scene's clamp distance alike.
    {"reports/summaries/fabric_text.cpp", "clamp_distance_m", "fabric record field"},
    {"reports/summaries/fabric_text.cpp", "compression_measured", "fabric record field"},
    // `db show` prints a knit record's pattern (fabric.yaml: chart, stitch length, yarn radius).
    {"reports/summaries/fabric_text.cpp", "chart_rows", "fabric record field"},
    {"reports/summaries/fabric_text.cpp", "stitch_length_mm", "fabric record field"},
    {"reports/summaries/fabric_text.cpp", "yarn_radius_mm", "fabric record field"},
    // `yarn sim` prints the scene's rest state (yarn_fit/scenes: the relaxation's own figures).
    {"yarn_fit/scenes/yarn_scene.cpp", "rest_stress_N_per_m", "yarn scene output"},
    {"shell_fit/scenes/scene_json.cpp", "clamp_distance_m", "pear-loop scene output of shell sim"},
    // The simulator commands' requests (pipeline/tools/) name their fields in their problems,
    // and the command line shows each as the option that sets it (cli/option_names.cpp): the
    // words of a request, not of a result file.
    {"pipeline/tools/make_tile.cpp", "chart", "tile make request field"},
    {"pipeline/tools/make_tile.cpp", "stitch_length_mm", "tile make request field"},
    {"pipeline/tools/make_tile.cpp", "yarn_radius_mm", "tile make request field"},
    {"pipeline/tools/synth_records.cpp", "directions", "synth request field"},
    {"cli/option_names.cpp", "chart", "request field shown as its option"},
    {"cli/option_names.cpp", "stitch_length_mm", "request field shown as its option"},
    {"cli/option_names.cpp", "yarn_radius_mm", "request field shown as its option"},
    {"cli/option_names.cpp", "directions", "request field shown as its option"},
};

// Files of another format that shares words with the result files: the yarn fit's checkpoint
// (yarn_fit/fit/fit_checkpoint.hpp: the alternation's rounds, the rescored starts) is the
// fit's own resumable state, read by nothing but the fit.
const std::set<std::string> k_other_formats = {"yarn_fit/fit/fit_checkpoint.cpp"};

bool excepted(const std::string& file, const std::string& key) {
  if (k_other_formats.count(file)) return true;
  for (const auto& e : k_exceptions)
    if (file == e.file && key == e.key) return true;
  return false;
}

TEST(ResultKeys, NoResultKeyIsAStringLiteralOutsideResults) {
  std::set<std::string> keys;
  for (const auto& k : result_keys())
    if (!k_words.count(k)) keys.insert(k);
  // Both files' own names are checked (a key list that went empty would pass anything).
  ASSERT_GT(keys.size(), 60u);
  for (const char* k : {"measured_force_N", "errors_by_direction", "stress_comfort_pct", "comfort_stretch",
                        "simulated_S_N_per_m", "range_alone_factor", "schema_version", "stitch_length_mm"})
    EXPECT_TRUE(keys.count(k)) << k;
  const fs::path root = YARNFIT_SOURCE_DIR;
  const std::regex literal("\"([A-Za-z_][A-Za-z0-9_]*)\"");
  std::vector<std::string> found;
  for (const char* module : {"reports", "batch", "cli", "pipeline", "shell_fit", "yarn_fit", "exports", "service"}) {
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
