// The slack reproducers of issue 37 (yarn_fit/generate/slack_tiles.hpp): every one builds as
// a valid tile, and the cheap ones (plain weave, loose stockinette; a second each) relax at
// rest and converge at every point of the 0–22 % free-compression sweep in weft, bias and warp.
// The iteration goal (median ≤ 30, max ≤ 200 a point) and the expensive tiles (basket,
// satin_small) are bench_yarn_fit's `slack` table, not this test.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/generate/slack_tiles.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

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
  EXPECT_THROW(make_slack_reproducer("no_such_tile"), std::invalid_argument);
}

TEST(SlackReproducers, CheapOnesConvergeAtEveryPointOfTheirSweeps) {
  for (const std::string name : {"plain_R0.25", "loose_st_R0.35"}) {
    const SlackReproducer r = make_slack_reproducer(name);
    YarnSystem rest_system(make_yarn_tile(r.tile), r.params);
    Eigen::VectorXd rest = Eigen::VectorXd::Zero(rest_system.dof_count());
    const RestShapeResult relaxed = relax_rest_shape(rest_system, rest);
    ASSERT_TRUE(relaxed.converged) << name << ": " << relaxed.last_solve.message;
    for (const double angle : {weft_angle(), bias_angle(), warp_angle()}) {
      SCOPED_TRACE(name + " at " + std::to_string(angle) + " rad");
      YarnSystem system = rest_system;
      Eigen::VectorXd g = rest;
      const StretchSweep sweep = sweep_stretch(system, angle, even_stretches(0.22, 23), g);
      EXPECT_EQ(sweep.failures, 0);
      for (const Sample& s : sweep.points) {
        EXPECT_TRUE(s.ok) << "s " << s.chi.stretch << ": " << s.message;
        EXPECT_TRUE(std::isfinite(s.stress_s) && std::isfinite(s.energy_density));
      }
    }
  }
}

}  // namespace
}  // namespace yarnfit::yarn
