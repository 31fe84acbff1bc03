// The in-plane fit: recovery of known parameters from synthetic records made on a different
// mesh, noise, and honest identification (issue 3, acceptance 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "fabrics_db/records/fabric_reader.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"
#include "tests/test_support.hpp"
#include "tests/shell_fit/known_materials.hpp"

namespace yarnfit::shell {
namespace {

using namespace yarnfit::testing;

const InplaneParams k_truth = known::k_knit;

// Targets on the synthetic curves' own points: fitting over the whole simulated range puts the
// 6 targets of each 13-point curve exactly on data points, so no interpolation error enters.
// The thesis law (eq. 6.1) over every measured point: the records below are simulated with it.
// The stiffening law's tests set their model themselves.
InplaneFitOptions full_range() {
  InplaneFitOptions o;
  o.model = InplaneModel::thesis;
  o.max_line_force = std::numeric_limits<double>::infinity();
  return o;
}

db::Fabric synthetic(const ScratchDir& dir, double noise, bool bias, bool gauge) {
  SyntheticShellOptions o;
  o.params.inplane = k_truth;
  o.noise = noise;
  o.refinements = 1;  // the fit runs on the unrefined mesh
  if (!bias) o.max_stretch.erase(db::Direction::bias);
  if (gauge) {
    o.gauge_length = 0.07;
    o.gauge_width = 0.04;
  }
  write_synthetic_shell_fabric(o, dir / "syn");
  auto load = db::load_fabric(dir / "syn");
  EXPECT_TRUE(load.ok()) << load.problems.to_string();
  return *load.fabric;
}

void print(const InplaneFitResult& r) {
  std::cout << "fit: " << r.message << "\n  force " << r.stretch_force_pct << " %, compression "
            << r.compression_pct << " %, " << r.iterations << " iterations, " << r.simulations
            << " simulations, " << r.seconds << " s\n  params";
  const double v[6] = {r.params.kxx, r.params.kxy, r.params.kyy, r.params.kss, r.params.kn1, r.params.kn2};
  for (int i = 0; i < 6; ++i)
    std::cout << " " << k_inplane_param_names[i] << "=" << v[i] << " (±" << r.sensitivity_pct[i] << " %/%)";
  std::cout << "\n";
}

double param(const InplaneParams& p, const std::string& name) {
  if (name == "kxx") return p.kxx;
  if (name == "kxy") return p.kxy;
  if (name == "kyy") return p.kyy;
  if (name == "kss") return p.kss;
  if (name == "kn1") return p.kn1;
  return p.kn2;
}

// Identified parameters come back within 2 % from data simulated on a finer mesh. kn1 and kn2
// (the two area terms) move the curves so little that the Jacobian flags them as weakly
// identified: ~11 % per 1 % of data noise, so the sub-percent mesh difference moves them by a
// few percent. The fit must say so rather than present them as determined.
TEST(InplaneFit, RecoversKnownParametersFromAnotherMesh) {
  for (bool gauge : {false, true}) {
    ScratchDir dir("recover");
    const auto fabric = synthetic(dir, 0.0, true, gauge);
    const auto r = fit_inplane(fabric, full_range());
    print(r);
    SCOPED_TRACE(gauge ? "gauge marks" : "clamps and edges");
    EXPECT_TRUE(r.converged) << r.message;
    EXPECT_TRUE(r.not_identified.empty());
    EXPECT_EQ(r.weakly_identified, (std::vector<std::string>{"kn1", "kn2"}));
    for (const auto& name : r.identified) {
      const bool weak = std::find(r.weakly_identified.begin(), r.weakly_identified.end(), name) !=
                        r.weakly_identified.end();
      EXPECT_NEAR(param(r.params, name), param(k_truth, name), (weak ? 0.10 : 0.02) * param(k_truth, name))
          << name;
    }
    EXPECT_LT(r.stretch_force_pct, 1.0);
    EXPECT_LT(r.compression_pct, 1.0);
  }
}

// On the mesh the data were made with, every parameter comes back exactly: the fit itself
// (residuals, exact Jacobians, Ceres) adds no error.
// The stiffening model (issue 21): its parameters come back from weft, warp and bias records
// simulated with a lock-up on a finer mesh. The fit starts from the thesis model's fit, which
// cannot follow these curves (its errors are printed beside the stiffening fit's).
TEST(InplaneFit, StiffeningModelRecoversKnownLockupFromAnotherMesh) {
  // k_truth with lock-up (lxx bxx, lyy byy, lss bss) and its lateral shares (axx ayy).
  const InplaneParams truth{120.0, 35.0, 400.0, 30.0, 5.0, 8.0, 300.0, 3.0, 600.0, 1.5, 60.0, 2.0, 0.6, 0.3};
  ScratchDir dir("recover_lockup");
  SyntheticShellOptions o;
  o.params.inplane = truth;
  o.refinements = 1;
  write_synthetic_shell_fabric(o, dir / "syn");
  auto load = db::load_fabric(dir / "syn");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  InplaneFitOptions options = full_range();
  options.model = InplaneModel::stiffening;
  const auto r = fit_inplane(*load.fabric, options);
  print(r);
  std::cout << "  lock-up: lxx " << r.params.lxx << " bxx " << r.params.bxx << " lyy " << r.params.lyy << " byy "
            << r.params.byy << " lss " << r.params.lss << " bss " << r.params.bss << " axx " << r.params.axx
            << " ayy " << r.params.ayy << "\n  thesis model from the same "
            << "data: force " << r.thesis_stretch_force_pct << " %, compression " << r.thesis_compression_pct << " %\n";
  EXPECT_EQ(r.model, InplaneModel::stiffening);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.identified.size(), 14u);
  EXPECT_LT(r.stretch_force_pct, 1.0);
  EXPECT_LT(r.compression_pct, 1.0);
  EXPECT_GT(r.thesis_stretch_force_pct, 2.0 * r.stretch_force_pct);  // the lock-up is needed
  const auto fitted = to_array(r.params), known = to_array(truth);
  for (int k = 0; k < k_inplane_param_count; ++k) {
    const std::string name = k_inplane_param_names[k];
    const bool weak = std::find(r.weakly_identified.begin(), r.weakly_identified.end(), name) != r.weakly_identified.end();
    EXPECT_NEAR(fitted[static_cast<std::size_t>(k)], known[static_cast<std::size_t>(k)],
                (weak ? 0.25 : 0.05) * known[static_cast<std::size_t>(k)])
        << name << (weak ? " (weakly identified)" : "");
  }
}

TEST(InplaneFit, RecoversEveryParameterExactlyOnTheSameMesh) {
  ScratchDir dir("same");
  SyntheticShellOptions o;
  o.params.inplane = k_truth;
  o.refinements = 0;
  write_synthetic_shell_fabric(o, dir / "syn");
  const auto r = fit_inplane(*db::load_fabric(dir / "syn").fabric, full_range());
  EXPECT_TRUE(r.converged) << r.message;
  for (const auto& name : r.identified)
    EXPECT_NEAR(param(r.params, name), param(k_truth, name), 1e-4 * param(k_truth, name)) << name;
}

TEST(InplaneFit, ReportsItsErrorsWithNoise) {
  ScratchDir dir("noise");
  const auto fabric = synthetic(dir, 0.02, true, false);
  const auto r = fit_inplane(fabric, full_range());
  print(r);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_GT(r.stretch_force_pct, 0.1);  // noise cannot be fitted away …
  EXPECT_LT(r.stretch_force_pct, 5.0);  // … but the model still fits the trend
  EXPECT_LT(r.compression_pct, 5.0);
}

// The default law on a record without lock-up (eq. 6.1's data): one of its starts is the thesis
// fit itself, so it ends no worse than that fit, and it converges.
TEST(InplaneFit, StiffeningFitOfAThesisRecordIsNoWorseThanTheThesisFit) {
  ScratchDir dir("stiff_on_thesis");
  const auto fabric = synthetic(dir, 0.0, true, false);
  InplaneFitOptions options = full_range();
  options.model = InplaneModel::stiffening;
  const auto r = fit_inplane(fabric, options);
  print(r);
  EXPECT_TRUE(r.converged) << r.message;
  EXPECT_LE(r.stretch_force_pct, r.thesis_stretch_force_pct + 0.01);
  EXPECT_LE(r.compression_pct, r.thesis_compression_pct + 0.01);
  EXPECT_LT(r.stretch_force_pct, 1.0);
  EXPECT_LT(r.compression_pct, 1.0);
}

TEST(InplaneFit, WithoutABiasTestKssIsHeldAndSaidSo) {
  ScratchDir dir("nobias");
  const auto fabric = synthetic(dir, 0.0, false, false);
  const auto r = fit_inplane(fabric, full_range());
  ASSERT_EQ(r.not_identified.size(), 1u);
  EXPECT_EQ(r.not_identified[0].rfind("kss: no bias test", 0), 0u);
  EXPECT_DOUBLE_EQ(r.params.kss, r.start.kss);
  EXPECT_EQ(r.identified.size(), 5u);
}

TEST(InplaneFit, StartValuesComeFromTheData) {
  ScratchDir dir("start");
  const auto fabric = synthetic(dir, 0.0, true, false);
  const InplaneParams start = initial_inplane_guess(fabric);
  // Within a factor of 2 of the truth for the axial terms: slopes, not constants.
  EXPECT_GT(start.kxx, 0.5 * k_truth.kxx);
  EXPECT_LT(start.kxx, 2.0 * k_truth.kxx);
  EXPECT_GT(start.kyy, 0.5 * k_truth.kyy);
  EXPECT_LT(start.kyy, 2.0 * k_truth.kyy);
}

}  // namespace
}  // namespace yarnfit::shell
