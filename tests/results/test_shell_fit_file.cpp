// shell_fit.json as results::ShellFitFile (results/shell_fit_file.hpp): a real output round-trips
// to the same JSON, a file of schema version 1 still reads with the per-direction errors its
// readers computed, and a bad field is named.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "tests/test_support.hpp"

#include "results/metrics/error_metrics.hpp"
#include "results/shell_fit_file.hpp"

namespace yarnfit::results {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace yarnfit::testing;

// Equal figures, NaN equal to NaN (no figure on both sides), bit for bit otherwise.
void expect_same_figure(double a, double b, const std::string& what) {
  if (std::isnan(a) || std::isnan(b)) EXPECT_TRUE(std::isnan(a) && std::isnan(b)) << what << ": " << a << " vs " << b;
  else EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << what << ": " << a << " vs " << b;
}

// The per-direction errors as version 1's readers computed them: the shell metric of the JSON
// curves (null cells NaN), the same function the fit calls.
double reader_figure(const json& measured, const json& simulated) {
  if (!measured.is_array() || !simulated.is_array()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> m, s;
  for (const auto& x : measured) m.push_back(number_or_nan(x));
  for (const auto& x : simulated) s.push_back(number_or_nan(x));
  return shell_error_pct(m, s);
}

// A small synthetic fabric with a weft and a warp stretch test and a weft pear-loop test,
// fitted by the command line: a real shell_fit.json with the bending fit's part (a few seconds).
const fs::path& fitted_output() {
  static const ScratchDir dir("results_shell");
  static const fs::path file = [] {
    auto r = yarnfit::testing::run_cli(
        "synth shell --out " + quoted(dir / "syn") +
        " --weft 0.5 --bias 0 --warp 0.3 --refine 0 --points 5 --ktheta-weft 3e-6 --ktheta-bias 2.5e-6"
        " --ktheta-warp 2e-6 --bending weft --bend-points 3 --bend-mesh 4");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    r = yarnfit::testing::run_cli("shell fit " + quoted(dir / "syn") + " --out " + quoted(dir / "fit"));
    EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
    return dir / "fit" / "shell_fit.json";
  }();
  return file;
}

TEST(ShellFitFile, ARealOutputRoundTripsToTheSameJson) {
  const json written = json::parse(read_file(fitted_output()));
  EXPECT_EQ(written["schema_version"], k_shell_fit_schema_version);
  const ShellFitFile file = shell_fit_file_from_json(written);
  EXPECT_EQ(file.schema_version, k_shell_fit_schema_version);
  ASSERT_TRUE(file.bending.has_value());
  ASSERT_EQ(file.directions.size(), 2u);
  // Dumped text: null and NaN are the same figure in the file.
  EXPECT_EQ(to_json(file).dump(2), written.dump(2));
  EXPECT_EQ(to_json(shell_fit_file_from_json(to_json(file))).dump(), to_json(file).dump());
}

TEST(ShellFitFile, TheStoredPerDirectionErrorsAreTheFitsFiguresOfItsCurves) {
  const json written = json::parse(read_file(fitted_output()));
  const ShellFitFile file = shell_fit_file_from_json(written);
  for (const auto& d : written["directions"]) {
    const std::string dir = d["direction"];
    const ShellDirectionErrors e = file.direction_errors(dir);
    expect_same_figure(e.stretch_force_pct, reader_figure(d["measured_force_N"], d["simulated_force_N"]), dir + " force");
    expect_same_figure(e.compression_pct, reader_figure(d["measured_compression"], d["simulated_compression"]),
                       dir + " compression");
    EXPECT_TRUE(std::isfinite(e.stretch_force_pct)) << dir;
  }
  for (const auto& c : written["bending"]["curves"]) {
    const std::string dir = c["direction"];
    expect_same_figure(file.direction_errors(dir).bending_pct,
                       reader_figure(c["measured_aspect_ratio"], c["simulated_aspect_ratio"]), dir + " bending");
  }
  EXPECT_TRUE(std::isnan(file.direction_errors("bias").stretch_force_pct));  // no bias test
}

// tests/results/data/shell_fit_v1.json: written by yarnfit before the results module (commit
// bd6c6bd, `synth shell` + `shell fit` as fitted_output() runs them). Version 1 stored no
// per-direction errors; reading it computes them from the curves as the reports did.
TEST(ShellFitFile, AVersionOneFileStillReads) {
  const json v1 = json::parse(read_file(fs::path(YARNFIT_SOURCE_DIR) / "tests/results/data/shell_fit_v1.json"));
  ASSERT_FALSE(v1.contains("schema_version"));
  const ShellFitFile file = shell_fit_file_from_json(v1);
  EXPECT_EQ(file.schema_version, 1);
  EXPECT_EQ(file.fabric, v1["fabric"].get<std::string>());
  ASSERT_EQ(file.directions.size(), v1["directions"].size());
  for (const auto& d : v1["directions"]) {
    const std::string dir = d["direction"];
    expect_same_figure(file.direction_errors(dir).stretch_force_pct,
                       reader_figure(d["measured_force_N"], d["simulated_force_N"]), dir + " force");
    expect_same_figure(file.direction_errors(dir).compression_pct,
                       reader_figure(d["measured_compression"], d["simulated_compression"]), dir + " compression");
  }
  expect_same_figure(file.errors.stretch_force_pct, v1["errors"]["stretch_force_pct"].get<double>(), "force");
  // Written again it is the current version: the old file's content plus the new keys.
  json again = to_json(file);
  EXPECT_EQ(again["schema_version"], k_shell_fit_schema_version);
  EXPECT_TRUE(again.contains("errors_by_direction"));
  again.erase("schema_version");
  again.erase("errors_by_direction");
  EXPECT_EQ(again.dump(2), v1.dump(2));
}

TEST(ShellFitFile, ABadFieldIsNamed) {
  const json v1 = json::parse(read_file(fs::path(YARNFIT_SOURCE_DIR) / "tests/results/data/shell_fit_v1.json"));
  const auto message = [](const json& j) {
    try {
      (void)shell_fit_file_from_json(j);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  json bad = v1;
  bad["directions"][0]["stretch"][1] = "x";
  EXPECT_EQ(message(bad), "shell_fit.json: directions[0].stretch[1]: expected a number or null (found string)");
  bad = v1;
  bad.erase("params");
  EXPECT_EQ(message(bad), "shell_fit.json: expected params (the fitted parameters)");
  bad = v1;
  bad["schema_version"] = 99;
  EXPECT_NE(message(bad).find("shell_fit.json: schema_version: expected 1 to"), std::string::npos) << message(bad);
  bad = v1;
  bad["schema_version"] = 2;  // says version 2 but lacks what version 2 stores
  EXPECT_EQ(message(bad), "shell_fit.json: expected errors_by_direction (schema version 2 and later)");
  EXPECT_EQ(message(json::array()), "shell_fit.json: expected an object (found array)");
}

}  // namespace
}  // namespace yarnfit::results
