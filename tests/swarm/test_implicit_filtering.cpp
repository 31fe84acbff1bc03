// Implicit filtering with Gauss–Newton steps (swarm/implicit_filtering.hpp): reaches the known
// zero-residual minimum of least-squares benchmarks, follows the trend of a valley that is
// rough at small scales where COBYLA does not, and keeps the wrapper's promises (best point
// seen, bounds, budgets, failures reported, same run whatever the number of threads).

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "swarm/cobyla.hpp"
#include "numerics/util/error.hpp"
#include "swarm/implicit_filtering.hpp"

namespace yarnfit::swarm {
namespace {

// Least-squares benchmarks with a zero-residual minimum (Moré, Garbow & Hillstrom 1981).
struct LeastSquares {
  std::string name;
  std::vector<Parameter> parameters;
  ResidualObjective r;
  Eigen::VectorXd start;
  Eigen::VectorXd minimiser;
};

std::vector<LeastSquares> least_squares_table() {
  std::vector<LeastSquares> t;
  t.push_back({"rosenbrock",
               {{"x", -2.0, 2.0, false}, {"y", -2.0, 2.0, false}},
               [](const Eigen::VectorXd& x) { return Eigen::Vector2d(10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]).eval(); },
               Eigen::Vector2d(-1.2, 1.0),
               Eigen::Vector2d(1.0, 1.0)});
  t.push_back({"beale",
               {{"x", -4.5, 4.5, false}, {"y", -4.5, 4.5, false}},
               [](const Eigen::VectorXd& x) {
                 Eigen::Vector3d r;
                 const double c[3] = {1.5, 2.25, 2.625};
                 for (int i = 0; i < 3; ++i) r[i] = c[i] - x[0] * (1.0 - std::pow(x[1], i + 1));
                 return Eigen::VectorXd(r);
               },
               Eigen::Vector2d(1.0, 1.0),
               Eigen::Vector2d(3.0, 0.5)});
  // A decay curve y = a e^{−b t} + c sampled at 20 times, fitted with b searched per decade
  // (as the yarn fit searches its stiffnesses).
  t.push_back({"exponential_decay",
               {{"a", 0.1, 10.0, false}, {"b", 1e-2, 10.0, true}, {"c", -1.0, 1.0, false}},
               [](const Eigen::VectorXd& x) {
                 Eigen::VectorXd r(20);
                 for (int j = 0; j < 20; ++j) {
                   const double tj = 0.25 * j;
                   r[j] = x[0] * std::exp(-x[1] * tj) + x[2] - (2.0 * std::exp(-0.7 * tj) + 0.5);
                 }
                 return r;
               },
               Eigen::Vector3d(1.0, 0.1, 0.0),
               Eigen::Vector3d(2.0, 0.7, 0.5)});
  // Powell's badly scaled function: residuals of sizes 1e4 and 1 with a minimiser near the
  // bound of x (1.098e-5, 9.106).
  t.push_back({"powell_badly_scaled",
               {{"x", 0.0, 1e-3, false}, {"y", 0.0, 20.0, false}},
               [](const Eigen::VectorXd& x) {
                 return Eigen::Vector2d(1e4 * x[0] * x[1] - 1.0, std::exp(-x[0]) + std::exp(-x[1]) - 1.0001).eval();
               },
               Eigen::Vector2d(1e-4, 5.0),
               Eigen::Vector2d(1.098159329699759e-5, 9.106146739866915)});
  return t;
}

ImplicitFilteringSettings tight() {
  ImplicitFilteringSettings s;
  s.max_evaluations = 3000;
  s.min_scale = 1e-9;
  return s;
}

TEST(ImplicitFiltering, ReachesTheZeroResidualMinimumOfLeastSquaresBenchmarks) {
  std::printf("%-22s %12s %12s %6s %5s  %s\n", "function", "start g", "final g", "evals", "iters", "termination");
  for (const auto& b : least_squares_table()) {
    SCOPED_TRACE(b.name);
    const ParameterSpace space(b.parameters);
    const ImplicitFilteringSummary r = run_implicit_filtering(space, b.r, b.start, tight());
    ASSERT_TRUE(r.usable()) << r.message;
    std::printf("%-22s %12.3e %12.3e %6d %5zu  %s\n", b.name.c_str(), r.start_value, r.best_value, r.evaluations,
                r.history.size(), r.message.c_str());
    EXPECT_EQ(r.status, ImplicitFilteringStatus::converged) << r.message;
    EXPECT_LT(r.best_value, 1e-12);
    const Eigen::VectorXd u = space.to_unit(r.best_point), u_min = space.to_unit(b.minimiser);
    EXPECT_LT((u - u_min).cwiseAbs().maxCoeff(), 1e-5) << r.best_point.transpose();
    EXPECT_EQ(b.r(r.best_point).squaredNorm(), r.best_value);
    EXPECT_LE(r.best_value, r.start_value);
  }
}

// Rosenbrock's valley with a rough surface: residual noise of 3e-4 that changes completely
// over 1e-4 of the range. Its trend's minimum is (1, 1); g there is about 2 · (3e-4)².
ResidualObjective rough_rosenbrock() {
  return [](const Eigen::VectorXd& x) {
    const double noise = 3e-4 * std::sin(7.3e4 * x[0] + 3.1e4 * x[1]);
    return Eigen::Vector2d(10.0 * (x[1] - x[0] * x[0]) + noise, 1.0 - x[0] - noise).eval();
  };
}

TEST(ImplicitFiltering, FollowsARoughValleyWhereCobylaStalls) {
  const ParameterSpace space({{"x", -2.0, 2.0, false}, {"y", -2.0, 2.0, false}});
  const ResidualObjective r = rough_rosenbrock();
  const Eigen::Vector2d start(-1.2, 1.0);
  ImplicitFilteringSettings s;
  s.max_evaluations = 300;
  s.initial_scale = 0.05;
  s.min_scale = 1e-3;
  const ImplicitFilteringSummary filtered = run_implicit_filtering(space, r, start, s);
  CobylaSettings c;
  c.max_evaluations = filtered.evaluations;
  c.initial_step = 0.05;
  c.x_tolerance = 0.0;
  const CobylaSummary cobyla =
      run_cobyla(space, [&](const Eigen::VectorXd& x) { return r(x).squaredNorm(); }, start, c);
  std::printf("rough Rosenbrock, %d evaluations each: implicit filtering g %.3e at (%.4f, %.4f); COBYLA g %.3e at "
              "(%.4f, %.4f)\n",
              filtered.evaluations, filtered.best_value, filtered.best_point[0], filtered.best_point[1],
              cobyla.best_value, cobyla.best_point[0], cobyla.best_point[1]);
  ASSERT_TRUE(filtered.usable());
  EXPECT_LT(filtered.best_value, 1e-6);  // the noise floor is 1.8e-7
  EXPECT_NEAR(filtered.best_point[0], 1.0, 0.01);
  EXPECT_NEAR(filtered.best_point[1], 1.0, 0.02);
  EXPECT_LT(filtered.best_value, 0.01 * cobyla.best_value);
}

TEST(ImplicitFiltering, SameRunWithOneAndTwoThreads) {
  const ParameterSpace space({{"x", -2.0, 2.0, false}, {"y", -2.0, 2.0, false}});
  ImplicitFilteringSettings s;
  s.max_evaluations = 200;
  s.threads = 1;
  const ImplicitFilteringSummary one = run_implicit_filtering(space, rough_rosenbrock(), Eigen::Vector2d(-1.2, 1.0), s);
  s.threads = 2;
  const ImplicitFilteringSummary two = run_implicit_filtering(space, rough_rosenbrock(), Eigen::Vector2d(-1.2, 1.0), s);
  EXPECT_EQ(one.best_point, two.best_point);
  EXPECT_EQ(one.best_value, two.best_value);
  EXPECT_EQ(one.evaluations, two.evaluations);
  ASSERT_EQ(one.history.size(), two.history.size());
  for (std::size_t i = 0; i < one.history.size(); ++i) {
    EXPECT_EQ(one.history[i].value, two.history[i].value);
    EXPECT_EQ(one.history[i].move, two.history[i].move);
  }
}

// Every point the objective sees, kept from any thread.
struct ResidualLog {
  std::mutex mutex;
  std::vector<Eigen::VectorXd> x;
  std::vector<double> g;
};

ResidualObjective logged_residuals(const ResidualObjective& f, ResidualLog& log) {
  return [f, &log](const Eigen::VectorXd& x) {
    Eigen::VectorXd r = f(x);
    const std::lock_guard<std::mutex> lock(log.mutex);
    log.x.push_back(x);
    log.g.push_back(r.squaredNorm());
    return r;
  };
}

TEST(ImplicitFiltering, ReturnsTheBestPointSeenInsideTheBoundsAndTheBudget) {
  // Unconstrained minimum (2, −3, 50) outside the box: the answer is the corner, and the
  // stencil at the corner has one side only in every coordinate.
  const ParameterSpace space({{"a", -1.0, 1.0, false}, {"b", -1.0, 1.0, false}, {"k", 1e-2, 10.0, true}});
  const ResidualObjective f = [](const Eigen::VectorXd& x) {
    return Eigen::Vector3d(x[0] - 2.0, x[1] + 3.0, std::log(x[2] / 50.0)).eval();
  };
  for (int limit : {1, 6, 13, 400}) {
    SCOPED_TRACE(limit);
    ResidualLog log;
    ImplicitFilteringSettings s;
    s.max_evaluations = limit;
    s.initial_scale = 0.3;
    const ImplicitFilteringSummary r = run_implicit_filtering(space, logged_residuals(f, log), Eigen::Vector3d(0.0, 0.0, 0.1), s);
    ASSERT_EQ(static_cast<int>(log.x.size()), r.evaluations);
    EXPECT_LE(r.evaluations, limit);
    for (const auto& x : log.x) ASSERT_TRUE(space.contains(x)) << x.transpose();
    const double best_seen = *std::min_element(log.g.begin(), log.g.end());
    EXPECT_EQ(r.best_value, best_seen);
    EXPECT_EQ(f(r.best_point).squaredNorm(), r.best_value);
    if (limit < 400) {
      EXPECT_EQ(r.status, ImplicitFilteringStatus::max_evaluations) << r.message;
    } else {
      EXPECT_EQ(r.status, ImplicitFilteringStatus::converged) << r.message;
      EXPECT_GT(r.evaluations, 13);
      EXPECT_NEAR(r.best_point[0], 1.0, 1e-12);
      EXPECT_NEAR(r.best_point[1], -1.0, 1e-12);
      EXPECT_NEAR(r.best_point[2], 10.0, 1e-10);
    }
  }
}

TEST(ImplicitFiltering, HonoursTheTimeLimitAndStopValue) {
  const ParameterSpace space({{"x", -2.0, 2.0, false}, {"y", -2.0, 2.0, false}});
  const ResidualObjective slow = [](const Eigen::VectorXd& x) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return Eigen::Vector2d(10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]).eval();
  };
  ImplicitFilteringSettings s;
  s.max_evaluations = 100000;
  s.min_scale = 1e-12;
  s.max_seconds = 0.05;
  s.threads = 1;
  ImplicitFilteringSummary r = run_implicit_filtering(space, slow, Eigen::Vector2d(-1.2, 1.0), s);
  EXPECT_EQ(r.status, ImplicitFilteringStatus::max_time) << r.message;
  EXPECT_LT(r.evaluations, 100);  // 2 ms each: about 25 fit in 50 ms
  EXPECT_TRUE(r.usable());

  s.max_seconds = 0.0;
  s.stop_value = 0.5;
  r = run_implicit_filtering(space, slow, Eigen::Vector2d(-1.2, 1.0), s);
  EXPECT_EQ(r.status, ImplicitFilteringStatus::stop_value) << r.message;
  EXPECT_LE(r.best_value, 0.5);
  std::printf("%s\n", r.brief_report().c_str());
}

TEST(ImplicitFiltering, FailedEvaluationsAreLeftOutAndReported) {
  const ParameterSpace space({{"x", -2.0, 2.0, false}, {"y", -2.0, 2.0, false}});
  std::atomic<int> thrown{0}, nan{0};
  const ResidualObjective f = [&](const Eigen::VectorXd& x) {
    // A band the simulation cannot enter, between the start and the minimiser, and a
    // region that returns NaN.
    if (x[1] > 0.4 && x[1] < 0.45) {
      ++thrown;
      throw std::runtime_error("solver diverged");
    }
    if (x[0] < -1.5) {
      ++nan;
      return Eigen::Vector2d(NAN, 0.0).eval();
    }
    return Eigen::Vector2d(10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]).eval();
  };
  ImplicitFilteringSettings s = tight();
  const ImplicitFilteringSummary r = run_implicit_filtering(space, f, Eigen::Vector2d(-1.2, 1.0), s);
  std::printf("%s (%d threw, %d NaN)\n", r.brief_report().c_str(), thrown.load(), nan.load());
  EXPECT_EQ(r.failed, thrown + nan);
  EXPECT_GT(r.failed, 0);
  ASSERT_TRUE(r.usable());
  EXPECT_LT(r.best_value, 1e-12);
  ASSERT_FALSE(r.failures.empty());
  const bool named = r.failures.front().message == "objective threw: solver diverged" ||
                     r.failures.front().message == "objective threw: a residual is not finite";
  EXPECT_TRUE(named) << r.failures.front().message;

  // The start itself fails: nothing to refine, said so.
  const ImplicitFilteringSummary none = run_implicit_filtering(space, f, Eigen::Vector2d(0.0, 0.42), s);
  EXPECT_FALSE(none.usable());
  EXPECT_EQ(none.status, ImplicitFilteringStatus::start_failed);
  EXPECT_EQ(none.evaluations, 1);
  EXPECT_EQ(none.message, "the start could not be evaluated: objective threw: solver diverged");
  EXPECT_EQ(none.best_point, Eigen::Vector2d(0.0, 0.42));

  // A residual vector that changes length is a failure, not a crash.
  const ResidualObjective shifting = [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    if (x[0] > 0.1) return Eigen::VectorXd::Constant(3, x[0]);
    return Eigen::Vector2d(x[0] - 0.5, x[1]);
  };
  const ImplicitFilteringSummary shift = run_implicit_filtering(space, shifting, Eigen::Vector2d(0.0, 0.0), s);
  ASSERT_GT(shift.failed, 0);
  EXPECT_EQ(shift.failures.front().message,
            "objective threw: the residual vector has 3 entries, the start's had 2");
  EXPECT_LE(shift.best_point[0], 0.1);
}

TEST(ImplicitFiltering, InvalidSettingsAndStartNameTheField) {
  const ParameterSpace space({{"x", -2.0, 2.0, false}});
  const ResidualObjective f = [](const Eigen::VectorXd& x) { return x; };
  auto message_of = [&](const ImplicitFilteringSettings& s, const Eigen::VectorXd& start) {
    try {
      (void)run_implicit_filtering(space, f, start, s);
    } catch (const yarnfit::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ImplicitFilteringSettings s;
  s.min_scale = 0.5;
  EXPECT_NE(message_of(s, Eigen::VectorXd::Zero(1)).find("min_scale"), std::string::npos);
  s = {};
  s.shrink = 1.0;
  EXPECT_NE(message_of(s, Eigen::VectorXd::Zero(1)).find("shrink"), std::string::npos);
  s = {};
  EXPECT_EQ(message_of(s, Eigen::VectorXd::Constant(1, 3.0)),
            "implicit filtering start: 'x' (parameter 0) = 3 is outside its bounds [-2, 2]");
}

}  // namespace
}  // namespace yarnfit::swarm
