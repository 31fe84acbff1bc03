// The calibration driver: when nothing works, every candidate failing is reported with the
// reason, not thrown, and no parameters are passed off as a fit; stopping swarm candidates at
// their particle's best leaves the fit as it was; and the implicit-filtering local step,
// started off the truth, finds known parameters again.
#include <gtest/gtest.h>

#include <iostream>

#include "yarn_fit/fit/yarn_fit.hpp"
#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/yarn_fit/fit/stockinette_case.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::yarn {
namespace {

// A fit small enough for a test: the thesis's single swarm with the stencil local step (the
// staged search and the Gauss–Newton step: test_staged_fit.cpp), 2 samples per direction in
// both stages, 2 threads.
YarnFitSettings small_fit(int particles, int iterations, int local_evaluations) {
  YarnFitSettings s;
  s.global_method = GlobalMethod::swarm;
  s.local_method = LocalMethod::implicit_filtering;
  s.particles = particles;
  s.iterations = iterations;
  s.swarm_samples = 2;
  s.local_samples = 2;
  s.local_evaluations = local_evaluations;
  s.threads = 2;
  return s;
}

TEST(YarnCalibration, EveryCandidateFailingIsReportedWithItsReason) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const yarn::ParameterScales& scales = st.scales;
  const SyntheticYarnResult synth = st.synthesise(yarn::default_params(scales), {db::Direction::weft}, 0.1, 3);

  YarnFitSettings s = small_fit(3, 1, 2);
  s.objective.solve.max_iterations = 1;  // no equilibrium can converge: every evaluation fails
  for (const bool swarm : {true, false}) {
    s.swarm = swarm;
    const YarnFitResult r = fit_yarn_params(st.yarn_tile(), synth.targets, scales, s);
    EXPECT_FALSE(r.ok) << "swarm " << swarm;
    EXPECT_FALSE(r.final.ok);
    EXPECT_NE(r.message.find(swarm ? "every swarm candidate failed" : "failed"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("max_iterations"), std::string::npos) << r.message;  // the solver's reason kept
    EXPECT_TRUE(r.bending.directions.empty());
    const nlohmann::json j = results::to_json(to_file(r, s));
    EXPECT_FALSE(j["ok"].get<bool>());
    EXPECT_TRUE(j["objective"].is_null());
    // No final evaluation: no errors (null, never 0 or a partial direction's) and the reason.
    EXPECT_TRUE(r.final.directions.empty());
    for (const char* k : {"stress_comfort_pct", "stress_full_pct", "compression_pct", "bending_pct"})
      EXPECT_TRUE(j["errors"][k].is_null()) << k << " " << j["errors"];
    ASSERT_TRUE(j["errors_reason"].is_string());
    EXPECT_EQ(j["errors_reason"], r.message);
    EXPECT_TRUE(j["curves"].empty());
    EXPECT_TRUE(j["errors_by_direction"].empty());
  }
}

TEST(YarnFitSettings, EveryInvalidFieldIsNamed) {
  YarnFitSettings s;
  EXPECT_TRUE(s.problems().empty());
  s.particles = 1;
  s.swarm_samples = 1;
  s.local_compression_nodes = 1;
  s.threads = -1;
  s.resume = true;  // without a checkpoint
  s.alternation.rest_difference_step = 0.5;
  const auto problems = s.problems();
  std::vector<std::string> fields;
  for (const auto& p : problems.items()) fields.push_back(p.field);
  EXPECT_EQ(fields, (std::vector<std::string>{"particles", "swarm_samples", "local_compression_nodes", "threads", "resume",
                                              "alternation.rest_difference_step"}))
      << problems.to_string();
  EXPECT_EQ(problems.items()[0].to_string(), "particles: must be at least 2 (got 1)");
  EXPECT_EQ(problems.one_line().find("particles: must be at least 2 (got 1); swarm_samples:"), 0u) << problems.one_line();
  // Without the swarm its settings do not matter.
  s.swarm = false;
  s.resume = false;
  s.threads = 0;
  s.swarm_samples = 2;
  s.local_compression_nodes = 0;
  s.alternation.rest_difference_step = 0.0;  // never measured: valid
  EXPECT_TRUE(s.problems().empty()) << s.problems().to_string();
  EXPECT_ERROR((void)fit_yarn_params(yarn::YarnTile{}, {}, {1.0, 1.0}, [] {
    YarnFitSettings bad;
    bad.local_samples = 1;
    return bad;
  }()), yarnfit::ErrorCategory::input);
}

// Two ways to run the same fit: every swarm candidate simulated in full, or stopped once it
// cannot beat its particle's best. The fits must agree to the bit, and the second must have
// stopped some candidates (so that the comparison means something).
TEST(YarnCalibration, StoppingSwarmCandidatesAtTheCutoffLeavesTheFitUnchanged) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  const SyntheticYarnResult synth = st.synthesise(st.soft_toe_params(), {db::Direction::weft}, 0.15, 4);

  YarnFitSettings s = small_fit(6, 3, 2);
  s.bending_points = 0;
  s.swarm_cutoff = false;
  const YarnFitResult full = fit_yarn_params(st.yarn_tile(), synth.targets, st.scales, s);
  s.swarm_cutoff = true;
  const YarnFitResult cut = fit_yarn_params(st.yarn_tile(), synth.targets, st.scales, s);
  ASSERT_TRUE(full.ok && cut.ok) << full.message << cut.message;
  EXPECT_EQ(full.swarm_stopped, 0);
  EXPECT_GT(cut.swarm_stopped, 0) << "no candidate stopped: the comparison tests nothing";
  EXPECT_EQ(cut.swarm.best_value, full.swarm.best_value);
  EXPECT_EQ(cut.swarm.best_iteration, full.swarm.best_iteration);
  EXPECT_EQ(cut.swarm.best_particle, full.swarm.best_particle);
  EXPECT_EQ(cut.final.value, full.final.value);
  for (const double yarn::YarnParams::*field : {&yarn::YarnParams::ks1, &yarn::YarnParams::eps_s,
                                                &yarn::YarnParams::kb, &yarn::YarnParams::r1, &yarn::YarnParams::kc1})
    EXPECT_EQ(cut.params.*field, full.params.*field);
  std::cout << "[ cutoff   ] " << cut.swarm_stopped << " of " << cut.swarm.evaluations
            << " swarm candidates stopped; swarm " << full.seconds_swarm << " s in full, " << cut.seconds_swarm
            << " s with stops\n";
}

// The local step alone (no swarm), started off known parameters, on targets simulated from
// them: implicit filtering must come back to the truth, and beat COBYLA from the same start
// with the same budget (the objective's small-scale roughness; see LocalMethod). Linear
// stretch (ks1 = ks2, ε̄s = 0) keeps it to three parameters, weft and warp to 6 samples.
TEST(YarnCalibration, ImplicitFilteringLocalStepReturnsToKnownParameters) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  yarn::YarnParams truth = yarn::default_params(st.scales);
  truth.ks1 = st.scales.ks2;
  truth.eps_s = 0.0;
  truth.kb = 0.2 * st.scales.kb_base();
  truth.r1 = 0.9 * st.scales.r_est;
  truth.kc1 = 2.0 * st.scales.kc_base();
  const SyntheticYarnResult synth = st.synthesise(truth, {db::Direction::weft, db::Direction::warp}, 0.3, 31);

  YarnFitSettings s = small_fit(2, 1, 40);
  s.swarm = false;
  s.linear_stretch = true;
  s.local_samples = 6;
  s.bending_points = 0;
  s.profile_step = 0.0;
  yarn::YarnParams start = truth;
  start.kb *= 1.5;
  start.kc1 *= 0.7;
  start.r1 *= 1.005;
  s.start = start;
  const YarnFitResult r = fit_yarn_params(st.yarn_tile(), synth.targets, st.scales, s);
  s.local_method = LocalMethod::cobyla;
  const YarnFitResult c = fit_yarn_params(st.yarn_tile(), synth.targets, st.scales, s);
  ASSERT_TRUE(r.ok && c.ok) << r.message << c.message;
  EXPECT_EQ(r.local.method, LocalMethod::implicit_filtering);
  EXPECT_EQ(c.local.method, LocalMethod::cobyla);
  const auto off = [](double fitted, double known) { return fitted / known - 1.0; };
  for (const YarnFitResult* f : {&r, &c})
    std::cout << "[ local    ] " << f->local.report << "\n[ local    ] kb " << 100 * off(f->params.kb, truth.kb)
              << " %, R1 " << 100 * off(f->params.r1, truth.r1) << " %, kc1 " << 100 * off(f->params.kc1, truth.kc1)
              << " %\n";
  EXPECT_NEAR(r.local.start_value, c.local.start_value, 1e-12 * c.local.start_value);  // |r|² against g
  EXPECT_LT(r.local.best_value, 0.01 * r.local.start_value);
  EXPECT_LT(r.local.best_value, 0.5 * c.local.best_value);
  EXPECT_LT(std::abs(off(r.params.kb, truth.kb)), 0.1);
  EXPECT_LT(std::abs(off(r.params.kc1, truth.kc1)), 0.1);
  EXPECT_LT(std::abs(off(r.params.r1, truth.r1)), 0.002);
  EXPECT_EQ(r.params.ks1, st.scales.ks2);  // fixed by linear stretch, whatever the start said
  const nlohmann::json j = results::to_json(to_file(r, s));
  EXPECT_EQ(j["local"]["method"], "implicit-filtering");
  EXPECT_EQ(j["local"]["evaluations"].get<int>(), r.local.evaluations);
  ASSERT_EQ(j["local"]["history"].size(), static_cast<std::size_t>(r.local.iterations));
  EXPECT_EQ(j["local"]["history"].back()["best"].get<double>(), r.local.best_value);
  EXPECT_EQ(j["local"]["history"].back()["evaluations"].get<int>(), r.local.evaluations);
  EXPECT_EQ(results::to_json(to_file(c, s))["settings"]["local_method"], "cobyla");
  EXPECT_NEAR(j["settings"]["start"]["kb"].get<double>(), start.kb, 1e-12 * start.kb);
}

// A start outside the search bounds is refused before any simulation, naming each parameter.
TEST(YarnCalibration, StartOutsideTheBoundsIsRefusedNamingTheParameters) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const testcase::Stockinette st = testcase::load_stockinette();
  YarnFitSettings s = small_fit(2, 1, 5);
  s.swarm = false;
  yarn::YarnParams start = yarn::default_params(st.scales);
  start.r1 = 10.0 * st.scales.r_est;
  start.kb = 1e6 * st.scales.kb_base();
  s.start = start;
  try {
    (void)fit_yarn_params(st.yarn_tile(), {}, st.scales, s);
    FAIL() << "a start outside the bounds was accepted";
  } catch (const yarnfit::Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("yarn fit start: kb: ", 0), 0u) << what;
    EXPECT_NE(what.find("; R1: "), std::string::npos) << what;
    EXPECT_NE(what.find("is outside the search bounds"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace yarnfit::yarn
