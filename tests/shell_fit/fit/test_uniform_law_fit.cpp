// A shell law fitted to uniform samples (the inverse of the uniform targets) and a law run
// against a record's measured tests (issue 48, item 4).
#include <gtest/gtest.h>

#include <cmath>

#include "fabrics_db/records/fabric_reader.hpp"
#include "shell_fit/fit/record_errors.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"
#include "shell_fit/fit/uniform_law_fit.hpp"
#include "shell_fit/targets/uniform_targets.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::shell {
namespace {

using namespace yarnfit::testing;

TargetRanges ranges(bool bias) {
  TargetRanges r;
  r.max_stretch[0] = 0.5;
  if (bias) r.max_stretch[1] = 0.4;
  r.max_stretch[2] = 0.3;
  r.max_curvature[0] = 200.0;
  r.max_curvature[2] = 150.0;
  r.stretch_samples = 13;
  r.curvature_samples = 5;
  return r;
}

ShellParams stiffening_law() {
  ShellParams p;
  p.inplane = {120.0, 30.0, 300.0, 25.0, 4.0, 6.0, 40.0, 6.0, 90.0, 4.0, 5.0, 3.0, 0.4, 0.2};
  p.bending.ktheta = {2e-6, 3e-6, 4e-6};
  return p;
}

double relative_off(double a, double b) { return std::abs(a / b - 1.0); }

// The samples of a known law are reproduced by the fitted law (its misfit is small), and the
// law's values are recovered where the samples determine them.
TEST(UniformLawFit, ReproducesTheSamplesOfAKnownThesisLaw) {
  ShellParams truth;
  truth.inplane = {150.0, 40.0, 350.0, 30.0, 5.0, 8.0};
  truth.bending.ktheta = {2e-6, 3e-6, 4e-6};
  const auto samples = generate_uniform_targets(truth, ranges(true));
  const UniformLawFit fit = fit_law_to_samples(samples, InplaneModel::thesis);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_LT(fit.stress_misfit_pct, 0.05);
  EXPECT_LT(fit.compression_misfit_pct, 0.05);
  EXPECT_LT(fit.bending_misfit_pct, 1e-9);
  EXPECT_LT(relative_off(fit.params.bending.ktheta[0], 2e-6), 1e-9);
  EXPECT_LT(relative_off(fit.params.bending.ktheta[2], 4e-6), 1e-9);
  // The bias slot has no bending samples: the mean of the others.
  EXPECT_LT(relative_off(fit.params.bending.ktheta[1], 3e-6), 1e-9);
  EXPECT_LT(relative_off(fit.params.inplane.kyy - fit.params.inplane.kxy * fit.params.inplane.kxy / fit.params.inplane.kxx,
                     truth.inplane.kyy - truth.inplane.kxy * truth.inplane.kxy / truth.inplane.kxx),
            0.02);
}

TEST(UniformLawFit, ReproducesTheSamplesOfAStiffeningLawWithoutBias) {
  const ShellParams truth = stiffening_law();
  const auto samples = generate_uniform_targets(truth, ranges(false));
  const UniformLawFit fit = fit_law_to_samples(samples, InplaneModel::stiffening);
  ASSERT_TRUE(fit.ok) << fit.message;
  EXPECT_LT(fit.stress_misfit_pct, 0.5);
  EXPECT_LT(fit.compression_misfit_pct, 1.0);
  ASSERT_EQ(fit.held.size(), 1u);
  EXPECT_EQ(fit.held[0].rfind("kss", 0), 0u);
  // The thesis law alone cannot follow the lock-up: its misfit is what the stiffening buys.
  const UniformLawFit thesis = fit_law_to_samples(samples, InplaneModel::thesis);
  ASSERT_TRUE(thesis.ok) << thesis.message;
  EXPECT_GT(thesis.stress_misfit_pct, 5.0 * fit.stress_misfit_pct);
}

TEST(UniformLawFit, NoStretchSamplesIsAFailureNotAThrow) {
  const UniformLawFit fit = fit_law_to_samples({}, InplaneModel::thesis);
  EXPECT_FALSE(fit.ok);
  EXPECT_FALSE(fit.message.empty());
}

// A record simulated from a known law: that law reproduces its curves (to the mesh
// difference between the writer's refined mesh and the default one), a stiffer one does not.
TEST(RecordErrors, TheLawThatMadeARecordReproducesItAndAnotherDoesNot) {
  ScratchDir dir("record_errors");
  SyntheticShellOptions o;
  o.params = stiffening_law();
  o.max_stretch = {{db::Direction::weft, 0.4}, {db::Direction::warp, 0.25}};
  o.points = 7;
  o.bending_directions = {db::Direction::weft};
  o.bending_points = 3;
  write_synthetic_shell_fabric(o, dir / "f");
  const db::FabricLoad load = db::load_fabric(dir / "f");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const RecordErrors own = simulate_record_errors(*load.fabric, o.params);
  ASSERT_TRUE(own.ok) << own.message;
  EXPECT_LT(own.errors.stretch_force_pct, 2.0);
  EXPECT_LT(own.errors.compression_pct, 3.0);
  EXPECT_LT(own.errors.bending_pct, 2.0);
  ASSERT_EQ(own.by_direction.size(), 2u);
  EXPECT_LT(own.by_direction.at("weft").bending_pct, 2.0);
  EXPECT_TRUE(std::isnan(own.by_direction.at("warp").bending_pct));
  ShellParams stiffer = o.params;
  stiffer.inplane.kxx *= 1.5;
  stiffer.bending.ktheta[0] *= 3.0;
  const RecordErrors other = simulate_record_errors(*load.fabric, stiffer);
  ASSERT_TRUE(other.ok) << other.message;
  EXPECT_GT(other.by_direction.at("weft").stretch_force_pct, 10.0);
  EXPECT_GT(other.errors.bending_pct, 5.0);
}

}  // namespace
}  // namespace yarnfit::shell
