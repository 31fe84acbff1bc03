// The COBYLA wrapper (issue 5, acceptance 1): swarm + COBYLA reaches the known minimum of the
// smooth benchmark functions to 1e-6, and the wrapper returns the best point seen, stays in
// the bounds and the evaluation and time budgets, penalises failures and says why it stopped.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "swarm/cobyla.hpp"
#include "numerics/util/error.hpp"
#include "swarm/particle_swarm.hpp"
#include "tests/swarm/benchmark_functions.hpp"

namespace yarnfit::swarm {
namespace {

using yarnfit::swarm::testing::benchmark;
using yarnfit::swarm::testing::benchmark_table;

// Every point an objective was called at, with its value.
struct CallLog {
  std::vector<Eigen::VectorXd> x;
  std::vector<double> f;
};

Objective logged_calls(const Objective& f, CallLog& log) {
  return [f, &log](const Eigen::VectorXd& x) {
    log.x.push_back(x);
    const double v = f(x);
    log.f.push_back(v);
    return v;
  };
}

TEST(Cobyla, SwarmThenCobylaReachesTheMinimumOfSmoothFunctions) {
  // COBYLA's linear models follow Rosenbrock's curved valley slowly: NLopt's COBYLA alone
  // needs about 14,000 evaluations from (−1.2, 1) to reach 1e-7, with or without bounds.
  CobylaSettings local;
  local.max_evaluations = 50000;
  local.initial_step = 0.02;
  local.x_tolerance = 1e-12;
  std::printf("%-20s %12s %12s %6s  %s\n", "function", "swarm error", "final error", "evals", "termination");
  for (const auto& b : benchmark_table()) {
    if (!b.smooth) continue;
    SCOPED_TRACE(b.name);
    const ParameterSpace space = b.space();
    const SwarmSummary global = run_swarm(space, b.f, SwarmSettings{});
    ASSERT_TRUE(global.usable());
    const CobylaSummary r = run_cobyla(space, b.f, global.best_point, local);
    ASSERT_TRUE(r.usable());
    std::printf("%-20s %12.3e %12.3e %6d  %s\n", b.name.c_str(), global.best_value - b.minimum,
                r.best_value - b.minimum, r.evaluations, r.message.c_str());
    EXPECT_LE(r.best_value, global.best_value);
    EXPECT_NEAR(r.best_value, b.minimum, 1e-6);
    EXPECT_EQ(b.f(r.best_point), r.best_value);
  }
}

// A bumpy bowl: the noise makes COBYLA's last iterate differ from the best point it saw in
// some runs; in every run the wrapper must return the best of all evaluations.
TEST(Cobyla, ReturnsTheBestPointSeenNotTheLast) {
  const auto& b = benchmark("sphere_3d");
  const Objective bumpy = [&](const Eigen::VectorXd& x) {
    return b.f(x) + 0.05 * std::sin(1e3 * x.sum()) * std::sin(731.0 * x[0]);
  };
  int last_was_worse = 0;
  for (double start : {-4.0, -1.0, 2.0, 3.0, 4.5}) {
    CallLog log;
    CobylaSettings s;
    s.max_evaluations = 400;
    s.x_tolerance = 1e-6;  // converges: its last steps probe around the best point
    const CobylaSummary r = run_cobyla(b.space(), logged_calls(bumpy, log), Eigen::Vector3d::Constant(start), s);
    ASSERT_EQ(static_cast<int>(log.f.size()), r.evaluations);
    const auto best = std::min_element(log.f.begin(), log.f.end()) - log.f.begin();
    EXPECT_EQ(r.best_value, log.f[static_cast<std::size_t>(best)]);
    EXPECT_EQ(r.best_point, log.x[static_cast<std::size_t>(best)]);
    EXPECT_EQ(r.start_value, log.f.front());
    last_was_worse += log.f.back() > r.best_value;
    std::printf("start %4.1f: best %.6f at evaluation %td of %zu, last %.6f (%s)\n", start, r.best_value, best + 1,
                log.f.size(), log.f.back(), r.message.c_str());
  }
  EXPECT_GT(last_was_worse, 0);
}

TEST(Cobyla, EveryEvaluationInsideTheBoundsIncludingLogSpace) {
  // Unconstrained minimum (2, −3, 50) outside the box: the answer is the corner.
  const ParameterSpace space({{"a", -1.0, 1.0, false}, {"b", -1.0, 1.0, false}, {"k", 1e-2, 10.0, true}});
  const Objective f = [](const Eigen::VectorXd& x) {
    return std::pow(x[0] - 2.0, 2) + std::pow(x[1] + 3.0, 2) + std::pow(std::log(x[2] / 50.0), 2);
  };
  CallLog log;
  CobylaSettings s;
  s.initial_step = 0.5;  // big first steps, which would leave the box if not clamped
  s.max_evaluations = 500;
  const CobylaSummary r = run_cobyla(space, logged_calls(f, log), Eigen::Vector3d(0.0, 0.0, 0.1), s);
  for (const auto& x : log.x) ASSERT_TRUE(space.contains(x)) << x.transpose();
  EXPECT_NEAR(r.best_point[0], 1.0, 1e-6);
  EXPECT_NEAR(r.best_point[1], -1.0, 1e-6);
  EXPECT_NEAR(r.best_point[2], 10.0, 1e-5);
  std::printf("%s\n", r.brief_report().c_str());
}

TEST(Cobyla, HonoursTheEvaluationLimit) {
  const auto& b = benchmark("rosenbrock_4d");
  for (int limit : {1, 7, 30}) {
    CallLog log;
    CobylaSettings s;
    s.max_evaluations = limit;
    const CobylaSummary r = run_cobyla(b.space(), logged_calls(b.f, log), Eigen::Vector4d(-1.0, 1.0, -1.0, 1.0), s);
    EXPECT_EQ(r.evaluations, limit);
    EXPECT_EQ(static_cast<int>(log.f.size()), limit);
    EXPECT_EQ(r.status, CobylaStatus::max_evaluations);
    EXPECT_STREQ(to_string(r.status), "evaluation limit reached");
  }
}

TEST(Cobyla, HonoursTheTimeLimit) {
  const auto& b = benchmark("rosenbrock_2d");
  const Objective slow = [&](const Eigen::VectorXd& x) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return b.f(x);
  };
  CobylaSettings s;
  s.max_evaluations = 100000;
  s.max_seconds = 0.05;
  s.x_tolerance = 0.0;
  const CobylaSummary r = run_cobyla(b.space(), slow, Eigen::Vector2d(-1.5, 2.0), s);
  EXPECT_EQ(r.status, CobylaStatus::max_time);
  EXPECT_GT(r.evaluations, 0);
  EXPECT_LT(r.evaluations, 100);  // 2 ms each: about 25 fit in 50 ms
  EXPECT_TRUE(r.usable());
  std::printf("%s\n", r.brief_report().c_str());
}

TEST(Cobyla, ReportsConvergenceAndStopValue) {
  const auto& b = benchmark("booth_2d");
  CobylaSettings s;
  s.x_tolerance = 1e-6;
  s.max_evaluations = 1000;
  CobylaSummary r = run_cobyla(b.space(), b.f, Eigen::Vector2d(-5.0, 5.0), s);
  EXPECT_EQ(r.status, CobylaStatus::x_tolerance) << r.message;
  EXPECT_TRUE(is_converged(r.status));
  EXPECT_LT(r.best_value, 1e-6);

  s.stop_value = 1.0;
  r = run_cobyla(b.space(), b.f, Eigen::Vector2d(-5.0, 5.0), s);
  EXPECT_EQ(r.status, CobylaStatus::stop_value) << r.message;
  EXPECT_LE(r.best_value, 1.0);
}

TEST(Cobyla, FailingEvaluationsArePenalisedAndReported) {
  const auto& b = benchmark("booth_2d");  // minimiser (1, 3)
  int thrown = 0, nan = 0;
  const Objective f = [&](const Eigen::VectorXd& x) {
    if (x[0] < -2.0) {
      ++thrown;
      throw std::runtime_error("solver diverged");
    }
    if (x[1] > 6.0) {
      ++nan;
      return std::numeric_limits<double>::quiet_NaN();
    }
    return b.f(x);
  };
  CobylaSettings s;
  s.initial_step = 0.3;
  s.max_evaluations = 500;
  s.x_tolerance = 1e-10;
  // The start itself fails: COBYLA still finds the minimum.
  const CobylaSummary r = run_cobyla(b.space(), f, Eigen::Vector2d(-3.0, 5.0), s);
  EXPECT_TRUE(std::isinf(r.start_value));
  EXPECT_EQ(r.failed, thrown + nan);
  EXPECT_GT(thrown, 0);
  ASSERT_TRUE(r.usable());
  EXPECT_LT(r.best_value, 1e-8);
  ASSERT_FALSE(r.failures.empty());
  EXPECT_EQ(r.failures.front().message, "objective threw: solver diverged");
  EXPECT_EQ(r.failures.front().evaluation, 0);
  std::printf("%s (%d threw, %d NaN)\n", r.brief_report().c_str(), thrown, nan);

  const CobylaSummary none = run_cobyla(b.space(), [](const Eigen::VectorXd&) { return NAN; }, Eigen::Vector2d(0, 0));
  EXPECT_FALSE(none.usable());
  EXPECT_EQ(none.failed, none.evaluations);
  EXPECT_NE(none.message.find("every evaluation failed"), std::string::npos);
  EXPECT_EQ(none.best_point, Eigen::Vector2d(0, 0));
}

TEST(Cobyla, InvalidSettingsAndStartNameTheField) {
  const auto& b = benchmark("booth_2d");
  auto message_of = [&](const CobylaSettings& s, const Eigen::VectorXd& start) {
    try {
      (void)run_cobyla(b.space(), b.f, start, s);
    } catch (const yarnfit::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CobylaSettings s;
  s.max_evaluations = 0;
  EXPECT_NE(message_of(s, Eigen::Vector2d(0, 0)).find("max_evaluations"), std::string::npos);
  s = {};
  s.initial_step = 2.0;
  EXPECT_NE(message_of(s, Eigen::Vector2d(0, 0)).find("initial_step"), std::string::npos);
  s = {};
  EXPECT_EQ(message_of(s, Eigen::Vector2d(0, 11)), "cobyla start: 'x[1]' (parameter 1) = 11 is outside its bounds [-10, 10]");
}

}  // namespace
}  // namespace yarnfit::swarm
