// yarnfit synth shell → yarnfit shell fit: the command line round trip and the stable output
// names of SPEC §5 (shell_fit.json, uniform_targets.csv); yarnfit shell sim against independent
// computations; progress on a terminal only.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <vector>

#include "numerics/roots/bisection.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

using nlohmann::json;

// Rows of a curve CSV (comment lines and the header skipped).
std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// The uniform uniaxial state of the shell model with the pull along the weft, computed here
// from the energy (6.1) alone: λx = 1 + s, λy from ∂Ψ/∂λy = 0 by bisection, and the first
// Piola stress P = ∂Ψ/∂λx [N/m], which is the line force per unit rest width.
struct Uniform {
  double line_force = 0.0;
  double compression = 0.0;
};
Uniform uniform_weft(double kxx, double kxy, double kyy, double kn1, double kn2, double s) {
  const double lx = 1.0 + s;
  const auto dpsi = [&](double ly, bool along_x) {
    const double exx = 0.5 * (lx * lx - 1.0), eyy = 0.5 * (ly * ly - 1.0), J = lx * ly;
    const double area = 2.0 * kn1 * (J - 1.0) + 2.0 * kn2 * std::log(J) / J;  // ∂(area terms)/∂J
    return along_x ? (kxx * exx + kxy * eyy) * lx + area * ly : (kxy * exx + kyy * eyy) * ly + area * lx;
  };
  // ∂Ψ/∂λy < 0 at 1e-3, > 0 at 1.5: 200 halvings.
  numerics::BisectionOptions o;
  o.halvings = 200;
  const double ly =
      numerics::bisect([&](double l) -> std::optional<bool> { return dpsi(l, false) < 0.0; }, 1e-3, 1.5, o).x;
  return {dpsi(ly, true), 1.0 - ly};
}

TEST(ShellCli, SynthThenFitWritesTheSpecifiedOutputs) {
  ScratchDir dir("shellcli");
  auto r = run_cli("synth shell --out " + quoted(dir / "syn") + " --weft 0.6 --bias 0 --warp 0.3 --refine 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Never replaces a record without --force.
  r = run_cli("synth shell --out " + quoted(dir / "syn"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("exists; pass --force"), std::string::npos) << r.err;

  r = run_cli("shell fit " + quoted(dir / "syn") + " --out " + quoted(dir / "fit") + " --full-range");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const auto j = nlohmann::json::parse(read_file(dir / "fit" / "shell_fit.json"));
  for (const char* k : {"kxx", "kxy", "kyy", "kss", "kn1", "kn2", "ktheta_weft", "ktheta_bias", "ktheta_warp"})
    EXPECT_TRUE(j["params"].contains(k)) << k;
  for (const char* k : {"stretch_force_pct", "compression_pct", "bending_pct"}) EXPECT_TRUE(j["errors"].contains(k)) << k;
  EXPECT_TRUE(j.contains("identified") && j.contains("effects") && j.contains("timing_s"));
  // kss is held at its prior here (no bias test), so kxx absorbs some of the difference.
  EXPECT_NEAR(j["params"]["kxx"].get<double>(), 120.0, 12.0);
  // No bias test: kss is held and said so; no bending test: k_θ not fitted.
  const std::string not_identified = j["not_identified"].dump();
  EXPECT_NE(not_identified.find("kss: no bias test"), std::string::npos) << not_identified;
  EXPECT_NE(not_identified.find("no bending test"), std::string::npos) << not_identified;
  EXPECT_TRUE(j["params"]["ktheta_weft"].is_null());
  const std::string csv = read_file(dir / "fit" / "uniform_targets.csv");
  EXPECT_EQ(csv.rfind("direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N\n", 0), 0u);
  EXPECT_NE(csv.find("warp,stretch,0.3,"), std::string::npos);
}

TEST(ShellCli, InvalidFabricIsInvalidInput) {
  ScratchDir dir("shellcli");
  write_file(dir / "bad" / "fabric.yaml", "id: x\n");
  const auto r = run_cli("shell fit " + quoted(dir / "bad") + " --out " + quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("family: missing required key"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace yarnfit::testing

namespace yarnfit::testing {
namespace {

// A long strip read between gauge marks in its middle is uniform there: `shell sim`'s line
// force and compression agree with the uniform zero-orthogonal-stress solution computed above
// (the scene's own analytic check, issue 3 acceptance 2), within 1 %.
TEST(ShellCli, SimStretchAgreesWithTheUniformSolutionOnALongStrip) {
  const auto r = run_cli(
      "shell sim --scene stretch --direction weft --stretch 0.1,0.3,0.6 --kxx 150 --kxy 40 --kyy 300 --kss 25 "
      "--kn1 6 --kn2 9 --length-mm 600 --width-mm 30 --gauge-length-mm 200 --gauge-width-mm 20 --refine 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["scene"], "stretch");
  EXPECT_EQ(j["direction"], "weft");
  EXPECT_EQ(j["effects"], json::array({"membrane"}));
  EXPECT_TRUE(j["converged"].get<bool>());
  ASSERT_EQ(j["samples"].size(), 3u);
  for (const auto& smp : j["samples"]) {
    const double s = smp["stretch"].get<double>();
    const Uniform u = uniform_weft(150, 40, 300, 6, 9, s);
    SCOPED_TRACE(::testing::Message() << "s = " << s);
    EXPECT_TRUE(smp["converged"].get<bool>());
    EXPECT_NEAR(smp["line_force_N_per_m"].get<double>(), u.line_force, 0.01 * u.line_force);
    EXPECT_NEAR(smp["force_N"].get<double>(), u.line_force * 0.03, 0.01 * u.line_force * 0.03);
    EXPECT_NEAR(smp["compression"].get<double>(), u.compression, 0.01 * u.compression);
    EXPECT_GT(smp["newton_iterations"].get<int>(), 0);
    EXPECT_LT(smp["residual_N"].get<double>(), 1e-6 * smp["force_N"].get<double>());
    EXPECT_GE(smp["seconds"].get<double>(), 0.0);
  }
}

// With the same options, `shell sim` runs exactly the scenes whose curves `synth shell`
// writes (the library's clamped-stretch and pear-loop scenes): same numbers to the digits
// written.
TEST(ShellCli, SimReproducesTheSynthesisedCurves) {
  ScratchDir dir("shellsim");
  const std::string params = " --kxx 90 --kxy 20 --kyy 250 --kss 18 --kn1 4 --kn2 6 --ktheta-weft 3e-6 "
                             "--ktheta-bias 2.5e-6 --ktheta-warp 2e-6 --refine 0 --bend-mesh 4 ";
  auto r = run_cli("synth shell --out " + quoted(dir / "syn") + params +
                   "--weft 0 --warp 0 --bias 0.5 --points 3 --gauge-length-mm 70 --gauge-width-mm 40 "
                   "--bending warp --bend-points 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(run_cli("db validate " + quoted(dir / "syn")).exit_code, 0);
  const auto stretch = csv_rows(read_file(dir / "syn" / "stretch_bias.csv"));
  ASSERT_EQ(stretch.size(), 3u);  // the rest state and 2 stretches
  r = run_cli("shell sim --direction bias --stretch 0.25,0.5 --gauge-length-mm 70 --gauge-width-mm 40" + params);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  json j = json::parse(r.out);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& smp = j["samples"][i];
    EXPECT_NEAR(smp["stretch"].get<double>(), stretch[i + 1][0], 1e-9);
    EXPECT_NEAR(smp["force_N"].get<double>(), stretch[i + 1][1], 1e-9 * stretch[i + 1][1]);
    EXPECT_NEAR(smp["compression"].get<double>(), stretch[i + 1][2], 1e-9);
    EXPECT_NEAR(smp["line_force_N_per_m"].get<double>(), smp["force_N"].get<double>() / 0.06, 1e-9);
  }

  const auto bend = csv_rows(read_file(dir / "syn" / "bend_warp.csv"));
  ASSERT_EQ(bend.size(), 2u);  // 3 and 34 mm
  r = run_cli("shell sim --scene pear --direction warp --distance 3,34" + params);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_EQ(j["effects"], json::array({"membrane", "bending", "gravity"}));
  EXPECT_EQ(j["governing_ktheta"], "ktheta_warp");
  // The bending length (B/(ρ g))^(1/3) with B = 2 k_θ and the default 180 g/m².
  EXPECT_NEAR(j["bending_length_m"].get<double>(), std::cbrt(2.0 * 2e-6 / (0.18 * 9.81)), 2e-3 * 0.013);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& smp = j["samples"][i];
    EXPECT_TRUE(smp["converged"].get<bool>());
    EXPECT_NEAR(smp["clamp_distance_m"].get<double>() * 1e3, bend[i][0], 1e-9);
    EXPECT_NEAR(smp["aspect_ratio"].get<double>(), bend[i][1], 1e-9 * bend[i][1]);
    EXPECT_NEAR(smp["aspect_ratio"].get<double>(), smp["height_m"].get<double>() / smp["width_m"].get<double>(), 1e-12);
  }
  // Clamps further apart make a rounder loop.
  EXPECT_LT(j["samples"][1]["aspect_ratio"].get<double>(), j["samples"][0]["aspect_ratio"].get<double>());
}

TEST(ShellCli, SimReadsTheParametersOfAShellFit) {
  ScratchDir dir("shellsim");
  write_file(dir / "shell_fit.json",
             R"({"params": {"kxx": 80, "kxy": 10, "kyy": 200, "kss": 15, "kn1": 3, "kn2": 2,
                 "ktheta_weft": null, "ktheta_bias": null, "ktheta_warp": null}})");
  auto r = run_cli("shell sim --stretch 0.2 --refine 0 --params " + quoted(dir / "shell_fit.json") + " --kyy 210");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["params"]["kxx"].get<double>(), 80.0);
  EXPECT_EQ(j["params"]["kyy"].get<double>(), 210.0);  // the command line wins
  EXPECT_EQ(j["params"]["kn2"].get<double>(), 2.0);
  // A null k_θ (not fitted) leaves the default: the pear loop then says what it needs.
  r = run_cli("shell sim --scene pear --distance 10 --params " + quoted(dir / "shell_fit.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--ktheta-weft: 0: the pear loop needs a positive bending stiffness"), std::string::npos) << r.err;
  write_file(dir / "bad.json", R"({"params": {"kxx": "stiff"}})");
  r = run_cli("shell sim --stretch 0.2 --params " + quoted(dir / "bad.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("params.kxx: expected a number"), std::string::npos) << r.err;
  write_file(dir / "broken.json", "{not json");
  r = run_cli("shell sim --stretch 0.2 --params " + quoted(dir / "broken.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("not a JSON object"), std::string::npos) << r.err;
}

TEST(ShellCli, SimRejectsBadInputWithClearMessages) {
  const std::pair<const char*, const char*> cases[] = {
      {"shell sim", "--stretch: the clamped stretch needs one or more stretches"},
      {"shell sim --stretch 0.3,0.1", "--stretch: 0.1: stretches must increase"},
      {"shell sim --stretch 0.1 --kxx -5", "--kxx: -5: must be positive"},
      {"shell sim --stretch 0.1 --kxy 500", "--kxy: 500: the membrane stiffness is not positive definite"},
      {"shell sim --stretch 0.1 --gauge-width-mm 80", "--gauge-width-mm: 80: must lie between 0 and the width"},
      {"shell sim --stretch 0.1 --distance 5", "--distance: applies to --scene pear"},
      {"shell sim --scene pear --distance 10", "--ktheta-weft: 0: the pear loop needs a positive bending stiffness"},
      {"shell sim --scene pear --distance 90 --ktheta-weft 1e-6 --ktheta-bias 1e-6 --ktheta-warp 1e-6",
       "--distance: 90 mm: pear loop: no loop of length"},
      {"shell sim --scene pear --distance 10 --ktheta-weft 1e-6 --ktheta-bias 1e-6 --ktheta-warp 1e-6 "
       "--areal-density-gsm 0",
       "--areal-density-gsm: 0: the pear loop hangs under gravity"},
      {"shell sim --scene twist --stretch 0.1", "--scene: twist not in {stretch,pear}"},
      {"shell sim --stretch 0.1,abc", "Could not convert"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
  }
}

// A simulation that cannot reach equilibrium (a planar membrane pushed to half its length
// buckles in its plane) is a result, not a crash: the JSON says which stretch failed and
// why, later stretches are marked as not simulated, and the exit code is 1.
TEST(ShellCli, SimReportsANonConvergedSceneClearly) {
  const auto r = run_cli("shell sim --stretch -0.5,0.1 --refine 0 --mesh 10");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_NE(j["message"].get<std::string>().find("equilibrium at clamp stretch -0.5"), std::string::npos) << j["message"];
  ASSERT_EQ(j["samples"].size(), 2u);
  EXPECT_FALSE(j["samples"][0]["converged"].get<bool>());
  EXPECT_EQ(j["samples"][1]["message"], "not simulated: an earlier stretch failed");
  EXPECT_NE(r.err.find("shell sim: not converged"), std::string::npos) << r.err;
}

// Progress goes to a terminal only (SPEC §5): stage and directions, iteration of the stage's
// budget, best error, time and the time left (at most: Ceres may stop before its budget),
// rewritten in place; nothing when stderr is a file or with --quiet.
TEST(ShellCli, FitShowsProgressOnATerminalOnly) {
  ScratchDir dir("progress");
  ASSERT_EQ(run_cli("synth shell --out " + quoted(dir / "syn") + " --bias 0 --warp 0.3 --refine 0 --points 5").exit_code, 0);
  const std::string fit = quoted(YARNFIT_CLI) + " shell fit " + quoted(dir / "syn") + " --out " + quoted(dir / "fit");
  auto r = run_cli("shell fit " + quoted(dir / "syn") + " --out " + quoted(dir / "fit"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("iteration"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("shell fit of synthetic_shell"), std::string::npos) << r.out;
  if (std::system("script --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` to give the fit a terminal";
  // `script` runs the command on a pseudo-terminal and logs what it shows.
  const auto on_terminal = [&](const std::string& extra, const fs::path& log) {
    write_file(dir / "run.sh", fit + extra + " >/dev/null\n");
    const std::string cmd = "script -qec " + quoted(fs::path("sh " + (dir / "run.sh").string())) + " " + quoted(log) + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return read_file(log);
  };
  const std::string shown = on_terminal("", dir / "tty.log");
  // The default (stiffening) law fits eq. 6.1 first, then continues from five starts.
  for (const char* expected : {"\rshell fit: in-plane, eq. 6.1 first (weft, warp) start 1/3, iteration 1/8, best rms error ",
                               "\rshell fit: in-plane, eq. 6.1 first (weft, warp), iteration 1/1000, best rms error ",
                               "\rshell fit: in-plane, stiffening (weft, warp) start 5/5, iteration 1/8, best rms error ",
                               "\rshell fit: in-plane, stiffening (weft, warp), iteration 1/1000, best rms error "})
    EXPECT_NE(shown.find(std::string(expected).insert(1, "\033[K")), std::string::npos) << expected << "\n" << shown;
  EXPECT_NE(shown.find(" %, "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s"), std::string::npos) << shown;
  EXPECT_NE(shown.find(", at most "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s left in this stage"), std::string::npos) << shown;
  const std::string quiet = on_terminal(" --quiet", dir / "quiet.log");
  EXPECT_EQ(quiet.find("shell fit:"), std::string::npos) << quiet;
}

}  // namespace
}  // namespace yarnfit::testing
