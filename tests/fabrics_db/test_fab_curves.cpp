// A FAB test's cycles (fabrics_db/fab/fab_curves.hpp): the mean loading curve, the spread of
// the cycles and the hysteresis, on branches whose answers are known.
#include <cmath>

#include "fabrics_db/fab/fab_curves.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

// A stretch test of taut length 8 cm on a zero of `zero` N: cycle 1 loads to s = 0.1 with
// force k·s, cycle 2 to s = 0.2 with 0.8·k·s (a softer reloading); each relaxation retraces
// its loading at half the force.
db::FabTest progressive_stretch(double k, double zero) {
  db::FabTest t;
  t.name = "S2";
  t.kind = db::FabTestKind::stretch;
  t.clamp_distance = 0.08;
  t.strip_width = 0.05;
  t.zero_offset = zero;
  const double reach[2] = {0.1, 0.2}, stiffness[2] = {k, 0.8 * k};
  for (int c = 0; c < 2; ++c) {
    db::FabBranchCurve load, relax;
    load.cycle = relax.cycle = c + 1;
    relax.branch = db::FabBranch::relaxation;
    for (int i = -5; i <= 40; ++i) {  // from slack (s < 0) on
      const double s = reach[c] * i / 40.0;
      load.clamp_distance.push_back(t.clamp_distance * (1.0 + s));
      load.raw_force.push_back(zero + stiffness[c] * std::max(0.0, s));
    }
    for (std::size_t i = load.clamp_distance.size(); i-- > 0;) {
      relax.clamp_distance.push_back(load.clamp_distance[i]);
      relax.raw_force.push_back(zero + 0.5 * (load.raw_force[i] - zero));
    }
    t.branches.push_back(load);
    t.branches.push_back(relax);
  }
  return t;
}

TEST(FabCurves, StretchCurveIsTheMeanOfTheLoadingBranchesThatReachEachStretch) {
  const double k = 3.0, zero = -0.02;
  int dropped = -1;
  const auto c = db::fab_stretch_curve(progressive_stretch(k, zero), dropped);
  EXPECT_EQ(dropped, 0);
  ASSERT_EQ(c.size(), 41u);  // the widest branch's points from s = 0
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double s = c.stretch[i];
    const double expected = s <= 0.1 + 1e-12 ? 0.9 * k * s : 0.8 * k * s;  // both cycles, then the second
    EXPECT_NEAR(c.force[i], expected, 1e-12) << "s = " << s;
  }
}

TEST(FabCurves, SpreadAndHysteresisOfKnownCycles) {
  const auto f = db::fab_cycle_figures(progressive_stretch(3.0, -0.02), -0.02);
  EXPECT_EQ(f.loading_branches, 2);
  // Where both branches lie: (k − 0.8k) / 0.9k.
  EXPECT_NEAR(f.spread_pct, 100.0 * 0.2 / 0.9, 1e-9);
  // Relaxation at half the loading force: half the work comes back.
  EXPECT_NEAR(f.hysteresis_pct, 50.0, 1e-9);
}

TEST(FabCurves, OneCycleHasNoSpreadAndNoRelaxationNoHysteresis) {
  db::FabTest t = progressive_stretch(3.0, 0.0);
  t.branches = {t.branches[0]};
  const auto f = db::fab_cycle_figures(t, 0.0);
  EXPECT_EQ(f.loading_branches, 1);
  EXPECT_TRUE(std::isnan(f.spread_pct));
  EXPECT_TRUE(std::isnan(f.hysteresis_pct));
}

}  // namespace
}  // namespace yarnfit::testing
