// yarnfit yarn fit and yarnfit fit (issue 5 "Commands"): on a fabric and targets made by
// `yarnfit synth yarn` from the stockinette tile of ../shared (weft only, 0–15 %, 4 points),
// with tiny settings so that a run takes seconds: the JSON names of SPEC §5, the files
// written, refusal to overwrite without --force, and invalid input (exit 2 naming the file).
// Recovery and accuracy are the benchmark's business, not these tests'.
#include <nlohmann/json.hpp>

#include <memory>
#include <sstream>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::testing {
namespace {

using nlohmann::json;


// The thesis's single swarm and the stencil local step keep the arithmetic of evaluations simple
// (the staged search and the Gauss–Newton step are tested in tests/yarn_fit/fit).
const std::string k_tiny =
    " --global swarm --local implicit-filtering --particles 4 --iterations 2 --samples 3 --local-samples 4"
    " --local-evaluations 5 --threads 2 --quiet";

// One synthetic fabric and its targets for the whole suite (a few seconds to simulate).
class FitCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(shared_stockinette())) return;
    s_dir = std::make_unique<ScratchDir>("fitcli");
    db::Problems problems;
    const auto tile = db::read_pyp(shared_stockinette(), problems);
    ASSERT_TRUE(tile) << problems.to_string();
    const auto params = yarn::default_params({400.0, db::compute_tile_facts(*tile).r_est});
    write_file(*s_dir / "y.yaml", yarn::to_json(params).dump(2) + "\n");
    const auto r = run_cli("synth yarn --pattern " + quoted(shared_stockinette()) + " --params " + quoted(*s_dir / "y.yaml") +
                           " --out " + quoted(*s_dir / "syn") + " --max-stretch 0.15 --directions weft --points 4 -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { s_dir.reset(); }
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(shared_stockinette());
    ASSERT_TRUE(s_dir && fs::exists(fabric() / "fabric.yaml")) << "synth yarn failed in the suite set-up";
  }
  static fs::path fabric() { return *s_dir / "syn" / "fabric"; }
  static fs::path targets() { return *s_dir / "syn" / "uniform_targets.csv"; }
  static std::string yarn_fit(const fs::path& fab, const fs::path& csv, const fs::path& out) {
    return "yarn fit " + quoted(fab) + " --targets " + quoted(csv) + " --out " + quoted(out);
  }
  // A copy of the synthetic fabric with `from` replaced by `to` in its fabric.yaml.
  static fs::path edited_fabric(const std::string& name, const std::string& from, const std::string& to) {
    const fs::path dst = *s_dir / name;
    fs::remove_all(dst);
    fs::copy(fabric(), dst, fs::copy_options::recursive);
    std::string yaml = read_file(dst / "fabric.yaml");
    const auto at = yaml.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) yaml.replace(at, from.size(), to);
    write_file(dst / "fabric.yaml", yaml);
    return dst;
  }

  static std::unique_ptr<ScratchDir> s_dir;
};

std::unique_ptr<ScratchDir> FitCli::s_dir;

json read_json(const fs::path& file) {
  json j = json::parse(read_file(file), nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << file;
  return j;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(FitCli, YarnFitWritesTheSpecifiedJsonCurvesAndSummary) {
  const fs::path out = *s_dir / "yarn_out";
  const auto r = run_cli(yarn_fit(fabric(), targets(), out) + k_tiny);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << "--quiet printed: " << r.out;

  const json j = read_json(out / "yarn_fit.json");
  for (const char* k : {"ks1", "eps_s", "kb", "R1", "kc1", "ks2", "kc2", "R2"}) {
    ASSERT_TRUE(j["params"].contains(k)) << k;
    EXPECT_TRUE(j["params"][k].is_number()) << k;
    EXPECT_GE(j["params"][k].get<double>(), 0.0) << k;
  }
  for (const char* k : {"stress_comfort_pct", "stress_full_pct", "compression_pct"}) {
    ASSERT_TRUE(j["errors"].contains(k)) << k;
    EXPECT_TRUE(j["errors"][k].is_number()) << k;
  }
  EXPECT_TRUE(j["errors"].contains("bending_pct"));
  // Swarm, local step, the final evaluation, and the identifiability profile: 2 per parameter.
  ASSERT_TRUE(j.contains("identifiability"));
  EXPECT_TRUE(j["identifiability"]["computed"].get<bool>()) << j["identifiability"].dump();
  EXPECT_EQ(j["identifiability"]["evaluations"].get<int>(), 2 * 5);
  for (const char* k : {"ks1", "eps_s", "kb", "R1", "kc1"}) {
    const json& e = j["identifiability"]["parameters"][k];
    EXPECT_EQ(e["value"].get<double>(), j["params"][k].get<double>()) << k;
    EXPECT_TRUE(e.contains("range_factor") && e.contains("range_alone_factor") && e.contains("free")) << k;
  }
  EXPECT_EQ(j["evaluations"].get<int>(), 4 * 2 + j["local"]["evaluations"].get<int>() + 1 + 2 * 5);
  EXPECT_LE(j["local"]["evaluations"].get<int>(), 5);
  // Iteration 1 has no particle bests to stop at; iteration 2 may stop any of its 4.
  ASSERT_TRUE(j["swarm"]["stopped_at_cutoff"].is_number_integer());
  EXPECT_LE(j["swarm"]["stopped_at_cutoff"].get<int>(), 4);
  EXPECT_TRUE(j.contains("timing_s"));
  EXPECT_EQ(j["params"]["ks2"].get<double>(), 400.0);  // the record's yarn stiffness
  EXPECT_EQ(j["fabric"], "synthetic_yarn");

  // Curves: the 4 local-step samples of the one direction, targets beside the model.
  const auto csv = lines_of(read_file(out / "yarn_curves.csv"));
  ASSERT_EQ(csv.size(), 1u + 4u);
  EXPECT_EQ(csv[0],
            "direction,sample,stretch,target_S_N_per_m,simulated_S_N_per_m,target_compression,simulated_compression,"
            "weight");
  EXPECT_EQ(csv[1].rfind("weft,0,0,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[4].rfind("weft,3,0.15", 0), 0u) << csv[4];

  const std::string summary = read_file(out / "yarn_summary.txt");
  for (const char* expected : {"weft", "stress comfort", "ks1", "eps_s", "kb", "R1", "kc1", "in [", "swarm", "local",
                               "time: global", "c* at every sample", "stopped once they could not beat",
                               "identifiability", "before g doubles", "others re-fitted", ", profile "})
    EXPECT_NE(summary.find(expected), std::string::npos) << expected << "\n" << summary;
}

// Rotation of the material frame: the same tile turned by 90° in its file, with
// `weft_axis: y`, is the same fabric, and one objective evaluation must say so.
TEST_F(FitCli, WeftAlongTheTileYAxisIsTheSameFabricTurned) {
  db::Problems problems;
  const auto tile = db::read_pyp(fabric() / "tile.pyp", problems);
  ASSERT_TRUE(tile) << problems.to_string();
  db::PeriodicTile turned = *tile;  // (x, y) -> (-y, x): the weft (x) now runs along y
  std::swap(turned.period_x, turned.period_y);
  for (auto& q : turned.positions) q = {-q[1], q[0], q[2]};
  for (auto& d : turned.reference_directors) d = {-d[1], d[0], d[2]};
  for (auto& e : turned.edges) e = {e.v0, e.v1, -e.dy, e.dx};
  const fs::path dir = edited_fabric("weft_y", "weft_axis: x", "weft_axis: y");
  db::write_pyp(turned, dir / "tile.pyp");

  // One evaluation at the start point: COBYLA with a budget of one (the Gauss-Newton local
  // step would alternate with the rest shape for rounds, and compare two fits' endpoints).
  const std::string once =
      " --no-swarm --local cobyla --local-evaluations 1 --local-samples 3 --samples 3 --threads 2 --quiet";
  const auto a = run_cli(yarn_fit(fabric(), targets(), *s_dir / "weft_x_out") + once);
  const auto b = run_cli(yarn_fit(dir, targets(), *s_dir / "weft_y_out") + once);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const json ja = read_json(*s_dir / "weft_x_out" / "yarn_fit.json");
  const json jb = read_json(*s_dir / "weft_y_out" / "yarn_fit.json");
  const double ga = ja["objective"].get<double>(), gb = jb["objective"].get<double>();
  EXPECT_GT(ga, 0.0);
  // Equal to the solver's tolerance (the turned file differs by round-off); reading the
  // wrong axis as the weft would compare the warp response with weft targets instead.
  EXPECT_NEAR(gb, ga, 1e-5 * ga);
  EXPECT_NEAR(jb["errors"]["stress_full_pct"].get<double>(), ja["errors"]["stress_full_pct"].get<double>(),
              1e-5 * ja["errors"]["stress_full_pct"].get<double>());
  EXPECT_EQ(jb["params"], ja["params"]);
}

TEST_F(FitCli, YarnFitRefusesToOverwriteWithoutForceAndSaysWhereResultsAre) {
  const fs::path out = *s_dir / "overwrite";
  fs::create_directories(out);
  write_file(out / "yarn_fit.json", "mine\n");
  auto r = run_cli(yarn_fit(fabric(), targets(), out) + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((out / "yarn_fit.json").string() + ": exists (use --force"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(out / "yarn_fit.json"), "mine\n");
  EXPECT_FALSE(fs::exists(out / "yarn_curves.csv"));

  const std::string loud = " --no-swarm --local-samples 2 --local-evaluations 1 --threads 2";
  r = run_cli(yarn_fit(fabric(), targets(), out) + loud + " --force");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(read_json(out / "yarn_fit.json").is_discarded());
  EXPECT_NE(r.out.find("results in " + out.string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stress comfort"), std::string::npos) << r.out;
  // Not a terminal: no progress line.
  EXPECT_EQ(r.err.find("yarn fit synthetic_yarn:"), std::string::npos) << r.err;
}

// --start refines given parameters without the swarm: the fit starts there (its first local
// evaluation is the start's objective), yarn_fit.json records it, a yarn_fit.json works as
// the start file, and a start outside the search bounds exits 2 naming the file and key.
TEST_F(FitCli, StartRefinesGivenParametersAndLocalMethodIsRecorded) {
  const std::string few = " --local-samples 3 --local-evaluations 2 --threads 2 --quiet --no-profile";
  auto r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "start1") + few + " --local-method cobyla --start " +
                   quoted(*s_dir / "y.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json a = read_json(*s_dir / "start1" / "yarn_fit.json");
  EXPECT_EQ(a["settings"]["local_method"], "cobyla");
  EXPECT_EQ(a["local"]["method"], "cobyla");
  EXPECT_EQ(a["settings"]["particles"], 0);  // no swarm
  EXPECT_FALSE(a.contains("swarm"));
  const json y = read_json(*s_dir / "y.yaml");
  EXPECT_EQ(a["settings"]["start"]["kb"], y["kb"]);
  const std::string summary = read_file(*s_dir / "start1" / "yarn_summary.txt");
  EXPECT_NE(summary.find("no global search, started from --start"), std::string::npos) << summary;
  EXPECT_NE(summary.find("local step cobyla"), std::string::npos) << summary;

  // yarn_fit.json as the start: implicit filtering from the first fit's parameters.
  r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "start2") + few + " --local implicit-filtering --start " +
              quoted(*s_dir / "start1" / "yarn_fit.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json b = read_json(*s_dir / "start2" / "yarn_fit.json");
  EXPECT_EQ(b["local"]["method"], "implicit-filtering");
  EXPECT_EQ(b["settings"]["start"]["ks1"], a["params"]["ks1"]);
  EXPECT_EQ(b["local"]["evaluations"], 1);  // a budget of 2 is less than a stencil
  EXPECT_NEAR(b["local"]["start"].get<double>(), a["objective"].get<double>(), 1e-9 * a["objective"].get<double>());

  json outside = y;
  outside["R1"] = 10.0 * y["R1"].get<double>();
  write_file(*s_dir / "outside.yaml", outside.dump(2) + "\n");
  r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "start3") + few + " --start " + quoted(*s_dir / "outside.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((*s_dir / "outside.yaml").string() + ": R1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is outside the search bounds"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(*s_dir / "start3" / "yarn_fit.json"));

  r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "start4") + few + " --local-method simplex");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--local: simplex: not a local method"), std::string::npos) << r.err;
}

TEST_F(FitCli, FabricWithoutPatternOrStiffnessExits2NamingFabricYaml) {
  const fs::path no_pattern = edited_fabric("no_pattern", "pattern:\n  file: tile.pyp\n  weft_axis: x\n", "");
  auto r = run_cli(yarn_fit(no_pattern, targets(), *s_dir / "o1") + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((no_pattern / "fabric.yaml").string() + ": pattern: missing"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(*s_dir / "o1"));

  const fs::path no_stiffness = edited_fabric("no_stiffness", "    stiffness_N:", "    # stiffness_N:");
  r = run_cli(yarn_fit(no_stiffness, targets(), *s_dir / "o2") + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find((no_stiffness / "fabric.yaml").string() + ": yarns.stiffness_N: missing"), std::string::npos)
      << r.err;

  // The pipeline checks the record before its shell stage.
  r = run_cli("fit " + quoted(no_pattern) + " --out " + quoted(*s_dir / "o3") + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("pattern: missing"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(*s_dir / "o3" / "shell_fit.json"));
}

TEST_F(FitCli, BadOrMissingTargetsExit2NamingTheFile) {
  const fs::path bad = *s_dir / "bad_targets.csv";
  write_file(bad, "direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n"
                  "weft,stretch,0,0,0,,\nweft,stretch,0.1,abc,1,,\n");
  auto r = run_cli(yarn_fit(fabric(), bad, *s_dir / "o4") + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad.string() + ":3"), std::string::npos) << r.err;

  const fs::path missing = *s_dir / "no_such_targets.csv";
  r = run_cli(yarn_fit(fabric(), missing, *s_dir / "o5") + k_tiny);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(*s_dir / "o5" / "yarn_fit.json"));

  // --resume needs --checkpoint; option checks exit 2 as well.
  r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "o6") + " --resume");
  EXPECT_EQ(r.exit_code, 2);
  r = run_cli(yarn_fit(fabric(), targets(), *s_dir / "o6") + " --samples 1");
  EXPECT_EQ(r.exit_code, 2);
}

// The whole pipeline on the synthetic record (weft only, no bending test: the shell stage is
// the in-plane fit, about 2 s). The bundled example also fits end to end, but its pear-loop
// fit alone takes about 40 s, too long for a unit test.
TEST_F(FitCli, FitRunsShellThenYarnAndWritesBothStagesAndASummary) {
  const fs::path out = *s_dir / "pipeline";
  const std::string args = "fit " + quoted(fabric()) + " --out " + quoted(out) +
                           " --global swarm --local implicit-filtering --particles 2 --iterations 1 --samples 2"
                           " --local-samples 4 --local-evaluations 2 --threads 2 --no-profile";
  auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("shell fit of synthetic_yarn"), std::string::npos) << r.out;  // the shell command's own report
  EXPECT_NE(r.out.find("results in " + out.string()), std::string::npos) << r.out;

  const json shell = read_json(out / "shell_fit.json");
  for (const char* k : {"kxx", "kxy", "kyy", "kss", "kn1", "kn2"}) EXPECT_TRUE(shell["params"][k].is_number()) << k;
  EXPECT_TRUE(shell["errors"]["stretch_force_pct"].is_number());
  EXPECT_TRUE(fs::exists(out / "uniform_targets.csv"));
  const json yarn = read_json(out / "yarn_fit.json");
  EXPECT_TRUE(yarn["params"]["ks1"].is_number());
  EXPECT_TRUE(yarn["errors"]["stress_comfort_pct"].is_number());
  EXPECT_EQ(yarn["targets"], (out / "uniform_targets.csv").string());
  // No pear-loop tests, so no bending targets: nothing to check, and the JSON says so.
  EXPECT_TRUE(yarn["errors"]["bending_pct"].is_null());
  EXPECT_FALSE(yarn.contains("bending_check"));
  EXPECT_LT(yarn["timing_s"]["bending_check"].get<double>(), 0.01);  // returned at once
  EXPECT_FALSE(yarn.contains("identifiability"));                      // --no-profile
  EXPECT_EQ(yarn["timing_s"]["profile"].get<double>(), 0.0);

  const auto shell_csv = lines_of(read_file(out / "shell_curves.csv"));
  ASSERT_GE(shell_csv.size(), 2u);
  EXPECT_EQ(shell_csv[0], "direction,stretch,measured_force_N,simulated_force_N,measured_compression,simulated_compression");
  EXPECT_EQ(shell_csv[1].rfind("weft,", 0), 0u) << shell_csv[1];
  EXPECT_EQ(lines_of(read_file(out / "yarn_curves.csv")).size(), 1u + 4u);

  const std::string summary = read_file(out / "summary.txt");
  for (const char* expected : {"shell fit: converged", "force", "kxx", "not fitted: ktheta", "yarn fit: ok",
                               "stress comfort", "R1", "time per stage: shell"})
    EXPECT_NE(summary.find(expected), std::string::npos) << expected << "\n" << summary;

  // The one-fabric report (yarnfit report's files) beside them, and the line saying where.
  const json report = read_json(out / "report" / "report.json");
  ASSERT_EQ(report["fabrics"].size(), 1u);
  EXPECT_EQ(report["fabrics"][0]["id"], "synthetic_yarn");
  EXPECT_EQ(report["fabrics"][0]["metrics"]["yarn_stress_comfort_pct"], yarn["errors"]["stress_comfort_pct"]);
  EXPECT_TRUE(fs::exists(out / "report" / "index.html"));
  EXPECT_NE(r.out.find("report of 1 fabric (1 family, 0 not fitted) from 1 run: open "), std::string::npos) << r.out;

  // A second run would replace every one of those files: refused, nothing simulated.
  r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2);
  for (const char* f : {"shell_fit.json", "uniform_targets.csv", "shell_curves.csv", "yarn_fit.json", "yarn_curves.csv",
                        "summary.txt", "report/index.html"})
    EXPECT_NE(r.err.find((out / f).string() + ": exists (use --force"), std::string::npos) << f << "\n" << r.err;
}

// Every invalid option of the pipeline is named at once, before the shell stage runs (on the
// bundled example, which needs no shared data: nothing is simulated).
TEST(FitOptions, EveryInvalidOptionIsRefusedBeforeTheShellStage) {
  ScratchDir dir("fit_options");
  const fs::path example = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";
  const auto r = run_cli("fit " + quoted(example) + " --out " + quoted(dir / "out") +
                         " --particles 1 --samples 1 --local-method simplex --mesh -1");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  for (const char* option : {"--particles: must be at least 2 (got 1)", "--samples: must be at least 2 (got 1)",
                             "--local: simplex: not a local method", "--mesh: must be a positive cell size"})
    EXPECT_NE(r.err.find(option), std::string::npos) << option << "\n" << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));  // nothing ran, nothing was written
  // The same for `yarn fit` and `shell fit`.
  const auto y = run_cli("yarn fit " + quoted(example) + " --targets " + quoted(dir / "none.csv") + " --out " +
                         quoted(dir / "y") + " --particles 1 --local-samples 0");
  EXPECT_EQ(y.exit_code, 2);
  for (const char* needle : {"--particles: must be at least 2", "--local-samples: must be at least 2", "none.csv"})
    EXPECT_NE(y.err.find(needle), std::string::npos) << needle << "\n" << y.err;
  const auto s = run_cli("shell fit " + quoted(example) + " --out " + quoted(dir / "s") + " --refine 9 --threads 0");
  EXPECT_EQ(s.exit_code, 2);
  EXPECT_NE(s.err.find("--refine: must be 0 to 4 (got 9)"), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("--threads: must be 1 to 64 (got 0)"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(dir / "s"));
}

TEST_F(FitCli, HelpListsTheOptions) {
  auto r = run_cli("yarn fit --help");
  ASSERT_EQ(r.exit_code, 0);
  for (const char* o : {"--targets", "--particles", "--iterations", "--samples", "--local-samples", "--local-evaluations",
                        "--seed", "--threads", "--no-swarm", "--linear-stretch", "--no-rest-shape", "--relax-period", "--checkpoint",
                        "--resume", "--quiet", "--force", "--local-method", "--start", "--budget", "--global", "--starts"})
    EXPECT_NE(r.out.find(o), std::string::npos) << o;
  r = run_cli("fit --help");
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--mesh"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::testing
