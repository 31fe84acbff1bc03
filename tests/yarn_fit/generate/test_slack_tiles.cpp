// The slack reproducers of issue 37 (yarn_fit/generate/slack_tiles.hpp) and the shared
// satin_small: every one builds as a valid tile, relaxes at rest, and its 0–22 %
// free-compression sweeps in weft, bias and warp converge at every point within the issue's
// goals (Newton iterations a point: median ≤ 30, max ≤ 200; energy–stress consistency:
// median ≤ 1 %, 90th percentile ≤ 5 %), the figures bench_yarn_fit's `slack` table prints.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <set>
#include <string>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "tests/yarn_fit/yarn_fixtures.hpp"
#include "yarn_fit/generate/slack_figures.hpp"
#include "yarn_fit/generate/slack_tiles.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::yarn {
namespace {

TEST(SlackReproducers, EveryOneIsAValidTile) {
  std::set<std::string> constructions;
  for (const std::string& name : slack_reproducer_names()) {
    SCOPED_TRACE(name);
    const SlackReproducer r = make_slack_reproducer(name);
    EXPECT_EQ(r.name, name);
    constructions.insert(r.construction);
    db::Problems problems;
    ASSERT_TRUE(db::parse_pyp(db::format_pyp(r.tile), name, problems)) << problems.to_string();
    EXPECT_NO_THROW(YarnSystem(make_yarn_tile(r.tile), r.params));
  }
  EXPECT_EQ(constructions.size(), slack_reproducer_names().size()) << "each says what it is";
  EXPECT_ERROR(make_slack_reproducer("no_such_tile"), yarnfit::ErrorCategory::input);
}

// One tile's figures against the goals, with every point that missed them named.
void expect_goals(const std::string& name, const YarnTile& tile, const YarnParams& params) {
  SCOPED_TRACE(name);
  YarnSystem rest_system(tile, params);
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(rest_system.dof_count());
  const RestShapeResult relaxed = relax_rest_shape(rest_system, rest);
  ASSERT_TRUE(relaxed.converged) << relaxed.last_solve.message;
  const SlackFigures f = sweep_slack_tile(rest_system.tile(), params, rest);
  EXPECT_EQ(f.points, 69);
  for (const SlackDirection& d : f.directions)
    for (const Sample& s : d.sweep.points) {
      EXPECT_TRUE(s.ok) << d.direction << " s " << s.chi.stretch << ": " << s.message;
      EXPECT_TRUE(std::isfinite(s.stress_s) && std::isfinite(s.energy_density)) << d.direction << " s " << s.chi.stretch;
      EXPECT_LE(s.newton_iterations, 200) << d.direction << " s " << s.chi.stretch;
    }
  std::cout << "[ slack   ] " << name << ": iterations median " << f.median_iterations() << ", max "
            << f.max_iterations() << "; consistency median " << 100 * f.consistency_median() << " %, 90th "
            << 100 * f.consistency_90th() << " %\n";
  EXPECT_LE(f.median_iterations(), 30);
  EXPECT_LE(f.consistency_median(), 0.01);
  EXPECT_LE(f.consistency_90th(), 0.05);
  EXPECT_TRUE(f.meets());
}

TEST(SlackReproducers, EveryOneConvergesAtEveryPointWithinTheGoals) {
  for (const std::string& name : slack_reproducer_names()) {
    const SlackReproducer r = make_slack_reproducer(name);
    expect_goals(name, make_yarn_tile(r.tile), r.params);
  }
}

TEST(SlackReproducers, TheSharedSatinConvergesAtEveryPointWithinTheGoals) {
  YARNFIT_REQUIRE_SHARED(fixtures::kPatterns + "satin_small.pyp");
  db::Problems problems;
  const auto params = read_yarn_params(testing::shared_dir() / "data/yarn_params_0.1mm.yaml", std::nullopt, problems);
  ASSERT_TRUE(params) << problems.to_string();
  expect_goals("satin_small", make_yarn_tile(fixtures::load_tile("satin_small.pyp")), *params);
}

}  // namespace
}  // namespace yarnfit::yarn
