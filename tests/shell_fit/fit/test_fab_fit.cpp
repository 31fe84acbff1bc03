// A shell model against FAB tests (issue 51): a stretch test made from a known in-plane law is
// predicted back, and a known k_θ is found from loop bends whose load cell zeros are unknown.
#include <gtest/gtest.h>

#include <cmath>

#include "shell_fit/fit/fab_fit.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/loop_bend.hpp"
#include "tests/shell_fit/known_materials.hpp"

namespace yarnfit::shell {
namespace {

using known::k_knit;

// A test's loading branches (two cycles, the second further) at the given abscissae.
db::FabTest test_of(const std::string& name, db::FabTestKind kind, double length, double width,
                    const std::vector<double>& d, const std::vector<double>& f) {
  db::FabTest t;
  t.name = name;
  t.kind = kind;
  t.clamp_distance = length;
  t.strip_width = width;
  for (int cycle = 1; cycle <= 2; ++cycle) {
    db::FabBranchCurve b;
    b.cycle = cycle;
    const std::size_t n = cycle == 1 ? d.size() / 2 : d.size();
    b.clamp_distance.assign(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(n));
    b.raw_force.assign(f.begin(), f.begin() + static_cast<std::ptrdiff_t>(n));
    t.branches.push_back(b);
    db::FabBranchCurve r = b;  // relaxation: ignored by the comparisons
    r.branch = db::FabBranch::relaxation;
    for (double& x : r.raw_force) x *= 0.5;
    t.branches.push_back(r);
  }
  return t;
}

TEST(FabFit, PredictsAStretchTestMadeFromTheLaw) {
  const double L = 0.0208, W = 0.05, zero = -0.02;
  ClampedStretchSetup s;
  s.length = L;
  s.width = W;
  s.target_edge = 0.25 * L;
  const std::vector<double> stretches{0.01, 0.03, 0.05, 0.08, 0.11, 0.15};
  const auto run = ClampedStretchScene(s).run(k_knit, stretches);
  ASSERT_TRUE(run.ok) << run.message;
  std::vector<double> d{0.99 * L}, f{zero};  // one slack sample, reading the zero
  for (const auto& smp : run.samples) {
    d.push_back(L * (1.0 + smp.measured_stretch));
    f.push_back(smp.force + zero);
  }
  db::FabTest t = test_of("S1", db::FabTestKind::stretch, L, W, d, f);
  t.zero_offset = zero;
  const auto e = predict_fab_stretch(t, db::Direction::weft, k_knit);
  EXPECT_TRUE(e.converged) << e.message;
  EXPECT_LT(e.force_pct, 1.0);
  // Another law is told apart.
  InplaneParams stiffer = k_knit;
  stiffer.kxx *= 1.3;
  EXPECT_GT(predict_fab_stretch(t, db::Direction::weft, stiffer).force_pct, 10.0);
}

TEST(FabFit, FindsAKnownKthetaFromBendsWithUnknownZeros) {
  const double kt = 3e-6, rho = 0.15, W = 0.05;
  ShellParams truth;
  truth.inplane = k_knit;
  truth.bending.ktheta = {kt, kt, kt};
  std::vector<db::FabTest> tests;
  const struct {
    const char* name;
    db::FabTestKind kind;
    double length, zero;
  } specs[] = {{"U1", db::FabTestKind::up_bend, 0.0208, -0.014},
               {"D1", db::FabTestKind::down_bend, 0.0208, -0.034},
               {"D2", db::FabTestKind::down_bend, 0.081, 0.005}};
  for (const auto& sp : specs) {
    LoopBendSetup s;
    s.length = sp.length;
    s.width = 0.1 * sp.length;
    s.areal_density = rho;
    s.direction = sp.kind == db::FabTestKind::up_bend ? LoopDirection::up : LoopDirection::down;
    // Distances the fit does not simulate, from near mounting to a deep loop.
    std::vector<double> d;
    for (int i = 0; i < 9; ++i) d.push_back(sp.length * (0.94 - 0.035 * i));
    const auto run = LoopBendScene(s).run(truth, d);
    ASSERT_TRUE(run.ok) << run.message;
    std::vector<double> f;
    for (const auto& smp : run.samples) f.push_back(smp.force * W / s.width + sp.zero);
    std::reverse(d.begin(), d.end());  // the fit takes the samples in any order
    std::reverse(f.begin(), f.end());
    tests.push_back(test_of(sp.name, sp.kind, sp.length, W, d, f));
  }
  FabBendOptions o;  // a narrower search than the default keeps the test short
  o.ktheta_lower = 1e-6;
  o.ktheta_upper = 1e-5;
  o.tolerance = 4e-3;
  std::vector<const db::FabTest*> fitted;
  for (const auto& t : tests) fitted.push_back(&t);
  const auto fit = fit_fab_bends(fitted, db::Direction::weft, k_knit, rho, o);
  ASSERT_TRUE(fit.converged) << fit.message;
  EXPECT_NEAR(fit.ktheta, kt, 0.02 * kt);
  ASSERT_EQ(fit.tests.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(fit.tests[i].offset, specs[i].zero, 2e-4) << specs[i].name;
  EXPECT_LT(fit.force_pct, 2.0);
  EXPECT_FALSE(fit.on_bound);
}

}  // namespace
}  // namespace yarnfit::shell
