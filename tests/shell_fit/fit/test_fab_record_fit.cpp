// A FAB record end to end (issue 51): a FAB physics file written from a known shell law
// through the stretch and loop-bend scenes, imported as a user would (db::import_fab), and
// fitted back by the shell stage: the law's identified stiffnesses and each direction's k_θ
// within 2 %, the held-out 2 cm stretch predicted within 2 %, and the held-out list checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "results/shell_fit_file.hpp"
#include "shell_fit/fit/shell_fit.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/loop_bend.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::shell {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

constexpr double k_gf = 9.80665e-3;  // N
constexpr double k_cm = 0.01;        // m
constexpr double k_record_rho = 0.15;       // kg/m²
// Eq. 6.1's law [N/m] as far as a FAB can tell it: the rig measures no change of width, so the
// Poisson coupling kxy and the compression stiffness kn1 are held at 0 and kn2 at its weak
// barrier (inplane_fit.hpp), and the truth is taken there.
const InplaneParams k_record_truth{120.0, 0.0, 400.0, 30.0, 0.0, 1e-3 * std::sqrt(120.0 * 400.0)};
const std::map<db::Direction, double> k_ktheta{
    {db::Direction::weft, 2.5e-6}, {db::Direction::bias, 4e-6}, {db::Direction::warp, 6e-6}};

// One test's samplesTree: `cycles` progressive cycles over the points (distance [m], force
// [N]), cycle c reaching the first c/cycles of them; each relaxation retraces its loading.
json samples_tree(const std::vector<double>& d, const std::vector<double>& f, std::size_t slack, int cycles) {
  json tree = json::array();
  for (int c = 1; c <= cycles; ++c) {
    const std::size_t n = slack + (d.size() - slack) * static_cast<std::size_t>(c) / static_cast<std::size_t>(cycles);
    json loading = json::array(), relaxation = json::array();
    for (std::size_t i = 0; i < n; ++i) loading.push_back(d[i] / k_cm), loading.push_back(f[i] / k_gf);
    for (std::size_t i = n; i-- > 0;) relaxation.push_back(d[i] / k_cm), relaxation.push_back(f[i] / k_gf);
    tree.push_back(loading);
    tree.push_back(relaxation);
  }
  return tree;
}

json test_json(double length, const json& tree) {
  return {{"freq", 55}, {"width", 5}, {"length", length / k_cm}, {"samplesTree", tree},
          {"hwSerialNumber", 7}, {"hwVersion", 1}, {"testVersion", 15}, {"time", 1580128950}};
}

// A stretch test at taut length L of a 5 cm strip: five slack samples reading the zero, then
// the law through the clamped-strip scene.
json stretch_test(db::Direction dir, double L, double zero) {
  ClampedStretchSetup s;
  s.length = L;
  s.width = 0.05;
  s.material_angle = -db::pull_angle(dir);
  s.target_edge = std::min(5e-3, 0.25 * L);
  std::vector<double> stretches;
  for (int k = 1; k <= 12; ++k) stretches.push_back(0.012 * k);
  const auto run = ClampedStretchScene(s).run(k_record_truth, stretches);
  EXPECT_TRUE(run.ok) << run.message;
  std::vector<double> d, f;
  for (int k = 5; k >= 1; --k) d.push_back(L * (1.0 - 0.002 * k)), f.push_back(zero);
  d.push_back(L), f.push_back(zero);
  for (const auto& smp : run.samples) d.push_back(L * (1.0 + smp.measured_stretch)), f.push_back(smp.force + zero);
  return test_json(L, samples_tree(d, f, 6, 3));
}

// A loop bend at taut length L, the moving clamp brought from 0.95 L to 0.4 L.
json bend_test(db::Direction dir, double L, LoopDirection up_down, double zero) {
  LoopBendSetup s;
  s.length = L;
  s.width = 0.1 * L;
  s.material_angle = -db::pull_angle(dir);
  s.areal_density = k_record_rho;
  s.direction = up_down;
  ShellParams p;
  p.inplane = k_record_truth;
  p.bending.ktheta = {k_ktheta.at(dir), k_ktheta.at(dir), k_ktheta.at(dir)};
  std::vector<double> d;
  for (int i = 0; i < 9; ++i) d.push_back(L * (0.95 - 0.065 * i));
  const auto run = LoopBendScene(s).run(p, d);
  EXPECT_TRUE(run.ok) << run.message;
  std::vector<double> f;
  for (const auto& smp : run.samples) f.push_back(smp.force * 0.05 / s.width + zero);
  return test_json(L, samples_tree(d, f, 0, 3));
}

// The physics file of a fabric made of the law above.
json synthetic_fab() {
  json raw = json::object();
  const std::pair<const char*, db::Direction> grains[] = {
      {"L", db::Direction::warp}, {"W", db::Direction::weft}, {"B", db::Direction::bias}};
  for (const auto& [letter, dir] : grains)
    raw[letter] = {{"S1", stretch_test(dir, 2.03 * k_cm, -0.012)},
                   {"S2", stretch_test(dir, 8.1 * k_cm, 0.004)},
                   {"U1", bend_test(dir, 2.05 * k_cm, LoopDirection::up, -0.015)},
                   {"D1", bend_test(dir, 2.05 * k_cm, LoopDirection::down, -0.03)},
                   {"D2", bend_test(dir, 8.1 * k_cm, LoopDirection::down, 0.006)}};
  raw["M"] = k_record_rho * 1000.0;  // g/m²
  raw["T"] = test_json(0.0, json::array({json::array({0.025, -500.0, 0.02, -900.0})}));
  return {{"schema", "1.1"}, {"raw_data", raw}, {"custom", {{"browzwear", {{"name", "synthetic"}, {"category", "Knits"}}}}}};
}

double relative_gap(double a, double b) { return std::abs(a - b) / std::abs(b); }

TEST(FabRecordFit, AFabFileMadeFromAKnownLawIsFittedBackWithin2Percent) {
  testing::ScratchDir dir("fabfit");
  testing::write_file(dir / "synthetic.json", synthetic_fab().dump());
  db::FabImportOptions io;
  io.input = dir / "synthetic.json";
  io.output = dir / "record";
  io.denier = 150.0;
  const auto imported = db::import_fab(io);
  ASSERT_TRUE(imported.written) << imported.problems.to_string();
  const auto load = db::load_fabric(dir / "record");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();

  ShellFitOptions o;
  o.model = InplaneModel::thesis;
  o.threads = 2;
  // Two decades about the truths, scanned every half decade, keep the test short.
  o.fab_bends.ktheta_lower = 3e-7;
  o.fab_bends.ktheta_upper = 3e-5;
  o.fab_bends.scan_points = 5;
  const ShellFitResult r = fit_shell(*load.fabric, o);
  ASSERT_TRUE(r.converged()) << r.failure();
  ASSERT_TRUE(r.fab);
  // The stretch tests pin the tensile and shear stiffnesses.
  EXPECT_LT(relative_gap(r.params.inplane.kxx, k_record_truth.kxx), 0.02) << r.params.inplane.kxx;
  EXPECT_LT(relative_gap(r.params.inplane.kyy, k_record_truth.kyy), 0.02) << r.params.inplane.kyy;
  EXPECT_LT(relative_gap(r.params.inplane.kss, k_record_truth.kss), 0.02) << r.params.inplane.kss;
  ASSERT_EQ(r.fab->bends.size(), 3u);
  for (const auto& b : r.fab->bends) {
    EXPECT_TRUE(b.converged) << b.message;
    EXPECT_LT(relative_gap(b.ktheta, k_ktheta.at(b.direction)), 0.02) << db::to_string(b.direction) << " " << b.ktheta;
    EXPECT_LT(relative_gap(r.params.bending.ktheta[static_cast<std::size_t>(b.direction)], k_ktheta.at(b.direction)), 0.02);
  }
  // Every test, fitted or held out, within 2 % of its data; S1 held out.
  ASSERT_EQ(r.fab->tests.size(), 15u);
  for (const auto& t : r.fab->tests) {
    EXPECT_EQ(t.held_out, t.error.test == "S1") << t.error.test;
    EXPECT_LT(t.error.force_pct, 2.0) << db::to_string(t.direction) << " " << t.error.test;
    // The file's cycles retrace each other: no spread, no hysteresis.
    EXPECT_LT(t.cycles.spread_pct, 1e-6) << t.error.test;
    EXPECT_LT(t.cycles.hysteresis_pct, 1e-6) << t.error.test;
  }
  // shell_fit.json: the fitted tests under errors_by_direction, the held-out one apart.
  const json j = results::to_json(to_file(r));
  for (const char* d : {"weft", "bias", "warp"}) {
    EXPECT_LT(j["errors_by_direction"][d]["stretch_force_pct"].get<double>(), 2.0) << d;
    EXPECT_LT(j["errors_by_direction"][d]["bending_pct"].get<double>(), 2.0) << d;
    EXPECT_LT(j["held_out_errors_by_direction"][d]["S1"]["stretch_force_pct"].get<double>(), 2.0) << d;
  }
  EXPECT_EQ(j["fab"]["held_out"], json::array({"S1"}));
  EXPECT_FALSE(j["params"]["ktheta_weft"].is_null());
  const auto back = results::shell_fit_file_from_json(j, "shell_fit.json");
  ASSERT_TRUE(back.fab);
  EXPECT_EQ(back.fab->tests.size(), 15u);
  EXPECT_EQ(results::to_json(back), j);
}

TEST(FabRecordFit, TheHeldOutListIsChecked) {
  const auto problems = [](std::vector<std::string> held_out) {
    ShellFitOptions o;
    o.fab_held_out = std::move(held_out);
    return o.problems().to_string();
  };
  EXPECT_EQ(problems({"S1"}), "");
  EXPECT_EQ(problems({"S2", "U1", "D2"}), "");
  EXPECT_NE(problems({"S1", "S2"}).find("exactly one of S1 and S2"), std::string::npos);
  EXPECT_NE(problems({}).find("exactly one of S1 and S2"), std::string::npos);
  EXPECT_NE(problems({"S1", "X9"}).find("X9: not a FAB test"), std::string::npos);
  EXPECT_NE(problems({"S1", "U1", "U1"}).find("U1: named twice"), std::string::npos);
  EXPECT_NE(problems({"S1", "U1", "D1", "D2"}).find("every bend"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::shell
