// The fit of issue 33 end to end on small settings: the staged search and the Gauss–Newton
// alternation give bitwise the same result on 1 and 2 threads, and a fit stopped after any
// stage (or between its local runs) and resumed from its checkpoint ends bitwise where the
// uninterrupted fit does; the checkpoint holds what it says.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>
#include <iostream>

#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "yarn_fit/fit/yarn_fit.hpp"
#include "tests/yarn_fit/fit/stockinette_case.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::yarn {
namespace {

// Staged search and local step small enough for a test (2 samples per direction, weft only).
YarnFitSettings tiny_fit(int threads) {
  YarnFitSettings s;
  s.staged.contact = {4, 2, 2, 6};
  s.staged.all = {4, 2, 2, 6};
  s.staged.rescored = 3;
  s.staged.starts = 2;
  s.local_samples = 3;
  s.alternation.max_rounds = 2;
  s.alternation.iterations_per_round = 2;
  s.bending_points = 0;
  s.threads = threads;
  return s;
}

struct Case {
  testcase::Stockinette st;
  std::vector<db::DirectionTargets> targets;
};

const Case& stockinette_case() {
  static const Case c = [] {
    Case k{testcase::load_stockinette(), {}};
    k.targets = k.st.synthesise(k.st.soft_toe_params(), {db::Direction::weft}, 0.15, 4).targets;
    return k;
  }();
  return c;
}

void expect_same_fit(const YarnFitResult& a, const YarnFitResult& b, const std::string& label) {
  ASSERT_TRUE(a.ok && b.ok) << label << ": " << a.message << b.message;
  for (const double yarn::YarnParams::*field : {&yarn::YarnParams::ks1, &yarn::YarnParams::eps_s,
                                                &yarn::YarnParams::kb, &yarn::YarnParams::r1, &yarn::YarnParams::kc1})
    EXPECT_EQ(a.params.*field, b.params.*field) << label;
  EXPECT_EQ(a.final.value, b.final.value) << label;
  ASSERT_EQ(a.global.size(), b.global.size()) << label;
  for (std::size_t i = 0; i < a.global.size(); ++i) EXPECT_EQ(a.global[i].best, b.global[i].best) << label;
  ASSERT_EQ(a.local_runs.size(), b.local_runs.size()) << label;
  for (std::size_t i = 0; i < a.local_runs.size(); ++i) {
    EXPECT_EQ(a.local_runs[i].best_value, b.local_runs[i].best_value) << label << ", run " << i;
    EXPECT_EQ(a.local_runs[i].alternation.rounds.size(), b.local_runs[i].alternation.rounds.size()) << label;
  }
  EXPECT_EQ(a.profile.g_fit, b.profile.g_fit) << label;
}

TEST(StagedFit, OneAndTwoThreadsGiveTheSameBits) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const Case& c = stockinette_case();
  const YarnFitResult one = fit_yarn_params(c.st.yarn_tile(), c.targets, c.st.scales, tiny_fit(1));
  const YarnFitResult two = fit_yarn_params(c.st.yarn_tile(), c.targets, c.st.scales, tiny_fit(2));
  expect_same_fit(one, two, "1 vs 2 threads");
  // The stages ran as asked: contact, all, rescore; two local runs with their rounds.
  ASSERT_EQ(two.global.size(), 3u);
  EXPECT_EQ(two.global[0].name, "contact");
  EXPECT_EQ(two.global[0].evaluations, 8);
  EXPECT_EQ(two.global[1].name, "all");
  EXPECT_EQ(two.global[2].name, "rescore");
  ASSERT_EQ(two.local_runs.size(), 2u);
  for (const auto& run : two.local_runs) {
    EXPECT_EQ(run.method, LocalMethod::gauss_newton);
    EXPECT_FALSE(run.alternation.rounds.empty());
    EXPECT_LE(run.best_value, run.start_value);
  }
  EXPECT_TRUE(two.profile.computed && two.profile.from_jacobian) << two.profile.message;
  std::cout << "[ staged   ] g " << two.final.value << " after " << two.evaluations << " evaluations, "
            << two.seconds_total << " s; local: " << two.local.report << "\n";
}

// keep_going answers true `allowed` times, then false: the fit stops at the next poll (after
// a swarm iteration, before a local run).
std::function<bool()> stop_after(int allowed) {
  auto count = std::make_shared<int>(0);
  return [count, allowed] { return (*count)++ < allowed; };
}

TEST(StagedFit, StoppedAfterAnyStageResumesToTheSameBits) {
  YARNFIT_REQUIRE_SHARED(testcase::stockinette_pattern());
  const Case& c = stockinette_case();
  // One thread: the local runs then go one after the other, so that a stop can fall between them.
  const YarnFitResult whole = fit_yarn_params(c.st.yarn_tile(), c.targets, c.st.scales, tiny_fit(1));
  ASSERT_TRUE(whole.ok) << whole.message;
  // Polls: contact iterations 1–2, all iterations 3–4, then one before each local run (5, 6).
  for (const int allowed : {0, 2, 4, 5}) {  // inside contact, inside all, before the local runs, between them
    const testing::ScratchDir dir("staged_resume");
    YarnFitSettings s = tiny_fit(1);
    s.checkpoint = dir / "fit.json";
    s.keep_going = stop_after(allowed);
    const YarnFitResult stopped = fit_yarn_params(c.st.yarn_tile(), c.targets, c.st.scales, s);
    EXPECT_TRUE(stopped.stopped) << "allowed " << allowed;
    EXPECT_FALSE(stopped.ok);
    if (allowed >= 4) {  // the staged search finished: its rescore is in the checkpoint
      const FitCheckpoint cp = read_fit_checkpoint(s.checkpoint);
      ASSERT_TRUE(cp.rescored.has_value());
      EXPECT_EQ(cp.rescored->front().point, whole.local_runs.front().start_point);
      // Written with the first local run that finished.
      ASSERT_EQ(cp.local.size(), allowed >= 5 ? 2u : 0u);
      if (allowed >= 5) {
        EXPECT_TRUE(cp.local[0].has_value() && !cp.local[1].has_value());
      }
    }
    s.keep_going = {};
    s.resume = true;
    const YarnFitResult resumed = fit_yarn_params(c.st.yarn_tile(), c.targets, c.st.scales, s);
    expect_same_fit(whole, resumed, "stopped after " + std::to_string(allowed) + " polls");
  }
}


// Infinite and NaN values survive the round trip as strings; any other string where a
// number belongs is a damaged checkpoint and says so, never a NaN fed to a resumed fit.
TEST(FitCheckpointFile, NonFiniteNumbersRoundTripAndAStrayStringIsAnError) {
  testing::ScratchDir dir("fit_checkpoint_numbers");
  const auto file = dir / "fit.json";
  FitCheckpoint c;
  c.rescored = std::vector<GlobalCandidate>{
      {Eigen::Vector3d(1.0, std::numeric_limits<double>::infinity(), -0.5), std::numeric_limits<double>::quiet_NaN()}};
  write_fit_checkpoint(file, c);
  const FitCheckpoint back = read_fit_checkpoint(file);
  ASSERT_TRUE(back.rescored);
  EXPECT_EQ((*back.rescored)[0].point, (*c.rescored)[0].point);
  EXPECT_TRUE(std::isnan((*back.rescored)[0].value));
  std::string text = testing::read_file(file);
  const auto at = text.find("\"nan\"");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 5, "\"oops\"");
  testing::write_file(file, text);
  try {
    (void)read_fit_checkpoint(file);
    ADD_FAILURE() << "a stray string was read as a number";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rescored[0].value: expected a number, got \"oops\""), std::string::npos)
        << e.what();
  }
}

// A damaged checkpoint names the field it failed on, however deep (issue 52: the fuzz target
// holds the reader to its header, which promises the field).
TEST(FitCheckpointFile, ADamagedFieldIsNamedByItsPath) {
  testing::ScratchDir dir("fit_checkpoint_fields");
  const auto file = dir / "fit.json";
  FitCheckpoint c;
  AlternationSummary run;
  run.best_point = Eigen::Vector2d(1.0, 2.0);
  run.rounds.resize(2);
  c.local = {std::nullopt, run};
  write_fit_checkpoint(file, c);
  ASSERT_TRUE(read_fit_checkpoint(file).local[1].has_value());
  const std::string good = testing::read_file(file);
  const auto message_for = [&](const std::string& from, const std::string& to, std::size_t nth) {
    std::string text = good;
    std::size_t at = text.find(from);
    for (std::size_t k = 0; k < nth && at != std::string::npos; ++k) at = text.find(from, at + 1);
    EXPECT_NE(at, std::string::npos) << from;
    if (at == std::string::npos) return std::string();
    text.replace(at, from.size(), to);
    testing::write_file(file, text);
    try {
      (void)read_fit_checkpoint(file);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("(read without an error)");
  };
  EXPECT_NE(message_for("\"evaluations\": 0", "\"evaluations\": \"x\"", 0).find(
                "local[1].evaluations: expected a number, got \"x\""),
            std::string::npos);
  EXPECT_NE(message_for("\"accepted\": false", "\"accepted\": 3", 1).find(
                "local[1].rounds[1].accepted: expected true or false, got 3"),
            std::string::npos);
  EXPECT_NE(message_for("\"best_point\"", "\"best_pt\"", 0).find("local[1].best_point: missing"), std::string::npos);
}

}  // namespace
}  // namespace yarnfit::yarn
