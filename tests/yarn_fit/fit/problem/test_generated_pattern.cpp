// The tile of a record whose pattern names a knit (yarn_fit/fit/problem/generated_pattern.hpp):
// generated into the cache folder under a name made of its inputs, read back from there the
// next time instead of generated again, and made into a yarn-fit problem whose bounds are
// centred on the knit's yarn radius; a knit too short for its yarn is a problem naming the
// record's pattern.knit, and a knit without its tile is refused by make_yarn_fit_problem.
// Its candidates may relax the period again (ObjectiveOptions::rest_period, --relax-period).
#include <gtest/gtest.h>

#include <filesystem>

#include "yarn_fit/fit/objective/yarn_objective.hpp"
#include "yarn_fit/fit/problem/generated_pattern.hpp"
#include "yarn_fit/fit/problem/yarn_fit_problem.hpp"
#include "tests/example_fabric.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::yarn {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

db::Fabric knit_fabric(const std::string& chart, double stitch_length_mm, double radius_mm) {
  db::Fabric f = bundled_example();
  f.pattern = db::PatternRef{};
  f.pattern->knit = db::KnitSpec{*db::parse_knit_chart(chart), 1e-3 * stitch_length_mm, 1e-3 * radius_mm, std::nullopt};
  return f;
}

TEST(GeneratedPattern, MadeOnceIntoTheCacheAndReadFromItAfterwards) {
  ScratchDir dir("generated_pattern");
  db::Fabric first = knit_fabric("stockinette", 11.28, 0.74);
  db::Problems problems;
  EXPECT_FALSE(make_yarn_fit_problem(first, problems)) << "no tile yet";
  EXPECT_NE(problems.to_string().find("pattern.knit: the tile of this knit is not made yet"), std::string::npos)
      << problems.to_string();
  problems = {};
  ASSERT_TRUE(make_generated_pattern(first, dir / "tiles", problems)) << problems.to_string();
  const fs::path file = dir / "tiles" / "knit_k_L11.28mm_R0.74mm.pyp";
  EXPECT_EQ(first.pattern->file, file);
  ASSERT_TRUE(fs::is_regular_file(file));
  EXPECT_TRUE(fs::is_regular_file(dir / "tiles" / "knit_k_L11.28mm_R0.74mm.json"));
  EXPECT_TRUE(first.pattern->has_tile());
  EXPECT_EQ(first.pattern->facts.yarns.size(), 1u);

  // The second fabric of the same knit reads the file instead of generating it again.
  const auto written = fs::last_write_time(file);
  db::Fabric second = knit_fabric("stockinette", 11.28, 0.74);
  ASSERT_TRUE(make_generated_pattern(second, dir / "tiles", problems)) << problems.to_string();
  EXPECT_EQ(fs::last_write_time(file), written) << "generated again";
  EXPECT_EQ(second.pattern->tile.positions, first.pattern->tile.positions);

  const auto problem = make_yarn_fit_problem(second, problems);
  ASSERT_TRUE(problem) << problems.to_string();
  EXPECT_DOUBLE_EQ(problem->scales.r_est, 0.74e-3) << "bounds centred on the knit's radius";
  EXPECT_LT(second.pattern->facts.r_est, 0.74e-3) << "the relaxed yarns rest pressed together";
}

// A record's knitting gauge (issue 48): the tile is generated at its period, cached under a name
// that says the gauge, and every rest state of the fit holds that period (no period steps).
TEST(GeneratedPattern, AGaugeIsTheTilesPeriodThroughTheFit) {
  ScratchDir dir("generated_gauge");
  db::Fabric fabric = knit_fabric("stockinette", 11.28, 0.74);
  fabric.pattern->knit->gauge = db::KnittingGauge{56.0, 32.0};
  db::Problems problems;
  ASSERT_TRUE(make_generated_pattern(fabric, dir / "tiles", problems)) << problems.to_string();
  EXPECT_EQ(fabric.pattern->file, dir / "tiles" / "knit_k_L11.28mm_R0.74mm_C56_W32.pyp");
  EXPECT_NEAR(fabric.pattern->tile.period_x, 0.1 / 32.0, 1e-12);
  EXPECT_NEAR(fabric.pattern->tile.period_y, 0.1 / 56.0, 1e-12);
  auto problem = make_yarn_fit_problem(fabric, problems);
  ASSERT_TRUE(problem) << problems.to_string();
  EXPECT_TRUE(problem->hold_period);
  const YarnFitSettings settings = settings_for(*problem, YarnFitSettings{});
  EXPECT_EQ(settings.objective.rest.period_chord_steps, 0);
  // A candidate's rest state keeps the period.
  db::DirectionTargets weft{db::Direction::weft, {{0.0, 0.0, 0.0, true}, {0.2, 0.05, 50.0, true}}, {}};
  const YarnObjective objective(problem->tile, {weft}, settings.objective);
  const RestState rest = objective.rest_state(yarn::default_params(problem->scales));
  ASSERT_TRUE(rest.ok) << rest.message;
  EXPECT_NEAR(rest.system->tile().lattice(0, 0), 0.1 / 32.0, 1e-12);
  EXPECT_NEAR(rest.system->tile().lattice(1, 1), 0.1 / 56.0, 1e-12);
  EXPECT_TRUE(rest.rest.period_stretch.isZero());
  // Without a gauge, the rest states move the period (the chord steps).
  db::Fabric free = knit_fabric("stockinette", 11.28, 0.74);
  ASSERT_TRUE(make_generated_pattern(free, dir / "tiles", problems)) << problems.to_string();
  const auto free_problem = make_yarn_fit_problem(free, problems);
  ASSERT_TRUE(free_problem);
  EXPECT_FALSE(free_problem->hold_period);
  EXPECT_GT(settings_for(*free_problem, YarnFitSettings{}).objective.rest.period_chord_steps, 0);
}

TEST(GeneratedPattern, AStitchTooShortForItsYarnIsAProblemOfTheRecord) {
  ScratchDir dir("generated_pattern_short");
  db::Fabric f = knit_fabric("seed", 3.0, 1.0);
  db::Problems problems;
  EXPECT_FALSE(make_generated_pattern(f, dir / "tiles", problems));
  EXPECT_NE(problems.to_string().find("pattern.knit: make_knit_tile: a stitch length of 3"), std::string::npos)
      << problems.to_string();
  EXPECT_FALSE(fs::exists(dir / "tiles")) << "nothing written";
}

TEST(GeneratedPattern, AFabricWithATileIsLeftAlone) {
  ScratchDir dir("generated_pattern_file");
  db::Fabric f = bundled_example();
  const fs::path before = f.pattern->file;
  db::Problems problems;
  EXPECT_TRUE(make_generated_pattern(f, dir / "tiles", problems));
  EXPECT_EQ(f.pattern->file, before);
  EXPECT_FALSE(fs::exists(dir / "tiles"));
}

// Targets σ = k s with c = 0.3 s over 0–10 %, for the weft and the warp.
std::vector<db::DirectionTargets> linear_targets(double k) {
  std::vector<db::DirectionTargets> out;
  for (const db::Direction d : {db::Direction::weft, db::Direction::warp}) {
    db::DirectionTargets t{d, {}, {}};
    for (const double s : {0.0, 0.05, 0.1}) t.stretch.push_back({s, 0.3 * s, k * s, true});
    out.push_back(t);
  }
  return out;
}

// A candidate whose contact radius differs from the one the tile was generated with carries
// coarse stress at s = 0 in the generated period; with the period relaxed per candidate it
// starts from its own stress-free rest, as the targets do.
TEST(GeneratedPattern, ACandidateStartsFromItsOwnStressFreeRest) {
  ScratchDir dir("generated_pattern_rest");
  db::Fabric f = knit_fabric("stockinette", 11.28, 0.74);
  db::Problems problems;
  ASSERT_TRUE(make_generated_pattern(f, dir / "tiles", problems)) << problems.to_string();
  const auto problem = make_yarn_fit_problem(f, problems);
  ASSERT_TRUE(problem) << problems.to_string();
  ObjectiveOptions fixed = settings_for(*problem, {}).objective;
  EXPECT_FALSE(fixed.rest_period) << "off by default";
  fixed.samples = 2;
  ObjectiveOptions relaxed = fixed;
  relaxed.rest_period = true;

  // Near the default fit of the acrylic stockinette record: thinner contact, soft contact
  // barrier, almost no soft stretch phase.
  yarn::YarnParams params = yarn::default_params(problem->scales);
  params.eps_s = 1.5e-4;
  params.kb = 0.2 * problem->scales.kb_base();
  params.r1 = 0.66 * problem->scales.r_est;
  params.kc1 = 1e-2 * problem->scales.kc_base();
  const double k = 300.0;  // N/m: stress norm 30 N/m, period tolerance 0.3 N/m
  const auto with = YarnObjective(problem->tile, linear_targets(k), relaxed).evaluate(params);
  const auto without = YarnObjective(problem->tile, linear_targets(k), fixed).evaluate(params);
  ASSERT_TRUE(with.ok) << with.message;
  ASSERT_TRUE(without.ok) << without.message;
  EXPECT_TRUE(with.period.converged);
  EXPECT_GT(with.period.solves, 0);
  for (std::size_t d = 0; d < 2; ++d) {
    SCOPED_TRACE(d == 0 ? "weft" : "warp");
    const double norm = with.directions[d].scale.stress_norm;
    std::cout << "[ rest     ] S(0) " << without.directions[d].stress_sim.front() << " N/m in the generated period, "
              << with.directions[d].stress_sim.front() << " N/m relaxed (norm " << norm << " N/m)\n";
    EXPECT_LE(std::abs(with.directions[d].stress_sim.front()), 2e-2 * norm);
  }
  EXPECT_GT(std::max(std::abs(without.directions[0].stress_sim.front()), std::abs(without.directions[1].stress_sim.front())),
            5e-2 * with.directions[0].scale.stress_norm)
      << "the generated period is not a rest state of this candidate: nothing to relax";
}

}  // namespace
}  // namespace yarnfit::yarn
