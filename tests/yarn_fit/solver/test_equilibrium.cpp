// The yarn equilibrium (yarn_fit/solver/equilibrium.hpp) in the hard cases of SPEC §7: heavy
// initial overlap, compression near inversion, stretch to 160 %, biphasic onset near zero,
// large curvature, parameters at their bounds — finite, barrier never crossed, a status.

#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "tests/yarn_fit/yarn_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;

// Hard cases (issue 4 item 6): finite results and a converged or clearly failed solve.
void expect_stable(const Sample& s, const std::string& label) {
  EXPECT_TRUE(std::isfinite(s.energy_density)) << label;
  EXPECT_TRUE(std::isfinite(s.stress_s)) << label;
  if (s.ok) {
    EXPECT_TRUE(std::isfinite(s.last_solve.min_contact_distance)) << label;
    EXPECT_GT(s.last_solve.min_contact_distance, 0.0) << label << ": barrier crossed";
  } else {
    EXPECT_FALSE(s.message.empty()) << label << ": failure without a reason";
  }
  std::printf("%-28s ok %d  iterations %3d  Ψ %.4g J/m²  σ_s %.4g N/m  closest %.3g R  %s\n",
              label.c_str(), s.ok ? 1 : 0, s.newton_iterations, s.energy_density, s.stress_s,
              s.last_solve.min_contact_distance / 1e-3, s.message.c_str());
}

TEST_F(StockinetteSystem, HardCasesStayFiniteAndReportTheirStatus) {
  const YarnTile base = make_yarn_tile(tile);
  EquilibriumOptions o;
  o.max_iterations = 200;
  // Tile scaled by 0.9: heavy initial overlap.
  {
    db::PeriodicTile scaled = tile;
    for (auto& p : scaled.positions)
      for (double& c : p) c *= 0.9;
    scaled.period_x *= 0.9;
    scaled.period_y *= 0.9;
    for (double& l : scaled.rest_lengths) l *= 0.9;
    YarnSystem sys(make_yarn_tile(scaled), params);
    Eigen::VectorXd g;
    expect_stable(simulate_sample(sys, {0.0, 0.0, 0.0, 0.0}, g, o), "tile scaled by 0.9");
  }
  const auto run = [&](const YarnParams& p, const CoarseDeformation& chi, const std::string& label) {
    YarnSystem sys(base, p);
    Eigen::VectorXd g;
    expect_stable(simulate_sample(sys, chi, g, o), label);
  };
  run(params, {0.0, 0.3, 0.0, weft_angle()}, "compression c = 0.3");
  run(params, {1.6, 0.0, 0.0, weft_angle()}, "stretch s = 1.6");
  YarnParams onset = params;
  onset.eps_s = 1e-12;
  run(onset, {0.3, 0.0, 0.0, warp_angle()}, "eps_s -> 0");
  run(params, {0.0, 0.0, 1.0 / (5.0 * base.radius), weft_angle()}, "curvature 1/(5 R)");
  const auto facts = db::compute_tile_facts(tile);
  const ParameterScales sc{400.0, facts.r_est};
  YarnParams low = params, high = params;
  low.ks1 = 1e-3 * sc.ks2;
  low.kb = 1e-3 * sc.kb_base();
  low.r1 = 0.5 * sc.r_est;
  low.kc1 = 1e-2 * sc.kc_base();
  low.eps_s = 0.0;
  high.ks1 = sc.ks2;
  high.kb = 10 * sc.kb_base();
  high.r1 = 1.5 * sc.r_est;
  high.kc1 = 1e2 * sc.kc_base();
  high.eps_s = 0.15;
  run(low, {0.3, 0.0, 0.0, bias_angle()}, "parameters at lower bounds");
  run(high, {0.3, 0.0, 0.0, bias_angle()}, "parameters at upper bounds");
}

}  // namespace
}  // namespace yarnfit::yarn
