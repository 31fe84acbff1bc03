// The particle swarm on the benchmark table (issue 5, acceptance 1): it beats random search
// with the same budget, gives bitwise the same run with 1 and 2 threads, resumes from a
// checkpoint to bitwise the uninterrupted result, and survives failing evaluations.

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>

#include "swarm/particle_swarm.hpp"
#include "swarm/random.hpp"
#include "tests/swarm/benchmark_functions.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::swarm {
namespace {

using yarnfit::swarm::testing::benchmark;
using yarnfit::swarm::testing::benchmark_table;
using namespace yarnfit::testing;
namespace fs = std::filesystem;

// Best of `budget` points drawn uniformly in the unit cube of the space (so log-space
// parameters are sampled per decade, as the swarm samples them).
double random_search(const ParameterSpace& space, const Objective& f, int budget, std::uint64_t seed) {
  RandomStream rng(seed);
  double best = std::numeric_limits<double>::infinity();
  Eigen::VectorXd u(space.dimension());
  for (int k = 0; k < budget; ++k) {
    for (int c = 0; c < space.dimension(); ++c) u[c] = rng.uniform();
    best = std::min(best, f(space.from_unit(u)));
  }
  return best;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// Bitwise equality of everything a run reports except wall times (and, when
// `iteration_statistics` is false, each iteration's best and mean, which see lower bounds).
void expect_same_run(const SwarmSummary& a, const SwarmSummary& b, bool iteration_statistics = true) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_TRUE(same_bits(a.best_value, b.best_value)) << a.best_value << " vs " << b.best_value;
  ASSERT_EQ(a.best_point.size(), b.best_point.size());
  for (Eigen::Index i = 0; i < a.best_point.size(); ++i) {
    EXPECT_TRUE(same_bits(a.best_point[i], b.best_point[i])) << "best_point[" << i << "]";
  }
  EXPECT_EQ(a.best_iteration, b.best_iteration);
  EXPECT_EQ(a.best_particle, b.best_particle);
  EXPECT_EQ(a.evaluations, b.evaluations);
  EXPECT_EQ(a.failed, b.failed);
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t k = 0; k < a.history.size(); ++k) {
    SCOPED_TRACE("iteration " + std::to_string(k + 1));
    EXPECT_EQ(a.history[k].iteration, b.history[k].iteration);
    EXPECT_TRUE(same_bits(a.history[k].best_value, b.history[k].best_value));
    if (iteration_statistics) {
      EXPECT_TRUE(same_bits(a.history[k].iteration_best, b.history[k].iteration_best));
      EXPECT_TRUE(same_bits(a.history[k].mean_value, b.history[k].mean_value));
    }
    EXPECT_EQ(a.history[k].failed, b.history[k].failed);
    EXPECT_TRUE(same_bits(a.history[k].neighbour_distance, b.history[k].neighbour_distance));
    EXPECT_TRUE(same_bits(a.history[k].inertia, b.history[k].inertia));
  }
  ASSERT_EQ(a.failures.size(), b.failures.size());
  for (std::size_t k = 0; k < a.failures.size(); ++k) {
    EXPECT_EQ(a.failures[k].evaluation, b.failures[k].evaluation);
    EXPECT_EQ(a.failures[k].message, b.failures[k].message);
  }
}

TEST(ParticleSwarm, BeatsRandomSearchWithTheSameBudgetOnEveryFunction) {
  const SwarmSettings settings;  // defaults: 64 particles × 10 iterations
  const int budget = settings.particles * settings.iterations;
  const std::vector<std::uint64_t> seeds{1, 2, 3, 4, 5};
  std::printf("%-20s %14s %14s   (median best of %zu seeds, %d evaluations each)\n", "function", "swarm",
              "random search", seeds.size(), budget);
  for (const auto& b : benchmark_table()) {
    SCOPED_TRACE(b.name);
    const ParameterSpace space = b.space();
    std::vector<double> swarm_best, random_best;
    for (std::uint64_t seed : seeds) {
      SwarmSettings s = settings;
      s.seed = seed;
      const SwarmSummary r = run_swarm(space, b.f, s);
      ASSERT_TRUE(r.usable());
      ASSERT_EQ(r.evaluations, budget);
      swarm_best.push_back(r.best_value - b.minimum);
      random_best.push_back(random_search(space, b.f, budget, seed) - b.minimum);
    }
    const double sm = median(swarm_best), rm = median(random_best);
    std::printf("%-20s %14.3e %14.3e\n", b.name.c_str(), sm, rm);
    EXPECT_LT(sm, rm);
  }
}

TEST(ParticleSwarm, HistoryAndProgressCallbackPerIteration) {
  const auto& b = benchmark("rastrigin_3d");
  SwarmSettings s;
  s.particles = 16;
  s.iterations = 6;
  std::vector<int> seen;
  SwarmRunOptions o;
  o.progress = [&](const SwarmProgress& p) {
    seen.push_back(p.record.iteration);
    EXPECT_EQ(p.iterations, 6);
    EXPECT_EQ(p.evaluations, 16 * p.record.iteration);
    EXPECT_EQ(p.best_point.size(), 3);
    EXPECT_GE(p.seconds_left, 0.0);
    return true;
  };
  const SwarmSummary r = run_swarm(b.space(), b.f, s, o);
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3, 4, 5, 6}));
  ASSERT_EQ(r.history.size(), 6u);
  EXPECT_EQ(r.status, SwarmStatus::completed);
  EXPECT_DOUBLE_EQ(r.history.front().inertia, 0.0);  // no move into iteration 1
  EXPECT_DOUBLE_EQ(r.history[1].inertia, 0.9);
  EXPECT_DOUBLE_EQ(r.history.back().inertia, 0.1);
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    EXPECT_LE(r.history[k].best_value, r.history[k - 1].best_value);
    if (k >= 2) {
      EXPECT_LT(r.history[k].inertia, r.history[k - 1].inertia);
    }
  }
  EXPECT_EQ(r.history.back().best_value, r.best_value);
  EXPECT_EQ(b.f(r.best_point), r.best_value);
  EXPECT_TRUE(b.space().contains(r.best_point));
  std::printf("%s\n", r.brief_report().c_str());
}

// Each particle's evaluation takes a different, particle-dependent time (a sleep, so the
// second thread runs even on a busy machine), so with two threads the evaluations finish
// out of order; the result must not notice.
TEST(ParticleSwarm, BitwiseIdenticalWithOneAndTwoThreads) {
  std::set<int> threads_seen;
  for (const char* name : {"rastrigin_3d", "log_sphere_3d", "rosenbrock_4d"}) {
    SCOPED_TRACE(name);
    const auto& b = benchmark(name);
    std::mutex mutex;
    const ParticleObjective f = [&](const Eigen::VectorXd& x, const ParticleContext& c) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        threads_seen.insert(omp_get_thread_num());
      }
      std::this_thread::sleep_for(std::chrono::microseconds(40 * (c.particle % 5)));
      if (x[0] > 0.9 * b.parameters[0].upper) throw std::runtime_error("near the upper bound");
      return b.f(x);
    };
    SwarmSettings s;
    s.seed = 42;
    SwarmRunOptions one, two;
    one.threads = 1;
    two.threads = 2;
    const SwarmSummary r1 = run_swarm(b.space(), f, s, one);
    const SwarmSummary r2 = run_swarm(b.space(), f, s, two);
    std::printf("%s: 1 thread %.3f s, 2 threads %.3f s, best %.6e, %d failed\n", name, r1.seconds, r2.seconds,
                r2.best_value, r2.failed);
    expect_same_run(r1, r2);
  }
  EXPECT_EQ(threads_seen.size(), 2u) << "the second thread never evaluated a particle";
}

// The cutoff an evaluation sees is its particle's best so far, and an objective that stops
// at the cutoff (returning only a lower bound at or above it) leaves the run as it was: the
// same bests, in the same iterations, from the same particles.
TEST(ParticleSwarm, StoppingAtTheCutoffLeavesTheRunUnchanged) {
  const auto& b = benchmark("rastrigin_3d");
  SwarmSettings s;
  s.seed = 11;
  s.particles = 16;
  s.iterations = 8;
  const int n = s.particles;
  std::vector<double> own_best(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity());
  int bounded = 0, cutoff_mismatches = 0;
  std::mutex mutex;
  const ParticleObjective stopping = [&](const Eigen::VectorXd& x, const ParticleContext& c) {
    const double v = b.f(x);
    std::lock_guard<std::mutex> lock(mutex);
    auto& best = own_best[static_cast<std::size_t>(c.particle)];
    if (!same_bits(c.cutoff, best)) ++cutoff_mismatches;
    best = std::min(best, v);
    if (v < c.cutoff) return v;
    ++bounded;
    return c.cutoff;  // the weakest lower bound allowed
  };
  SwarmRunOptions two;
  two.threads = 2;
  const SwarmSummary exact = run_swarm(b.space(), b.f, s, two);
  const SwarmSummary cut = run_swarm(b.space(), stopping, s, two);
  EXPECT_EQ(cutoff_mismatches, 0);
  EXPECT_GT(bounded, n) << "the test must exercise the bound";
  expect_same_run(exact, cut, false);
}

TEST(ParticleSwarm, ResumeAfterAKillGivesTheUninterruptedResult) {
  const auto& b = benchmark("ackley_3d");
  const ScratchDir dir("swarm-resume");
  SwarmSettings s;
  s.seed = 7;
  SwarmRunOptions full_options;
  full_options.checkpoint = dir / "full.json";
  const SwarmSummary full = run_swarm(b.space(), b.f, s, full_options);

  // "Kill" after iteration 4: the callback stops the run once its checkpoint is on disk.
  SwarmRunOptions killed;
  killed.checkpoint = dir / "killed.json";
  killed.progress = [](const SwarmProgress& p) { return p.record.iteration < 4; };
  const SwarmSummary partial = run_swarm(b.space(), b.f, s, killed);
  EXPECT_EQ(partial.status, SwarmStatus::stopped);
  EXPECT_EQ(partial.history.size(), 4u);
  EXPECT_TRUE(fs::exists(dir / "killed.json"));
  EXPECT_FALSE(fs::exists(dir / "killed.json.tmp"));

  // Resume with another thread count: neither may change the result.
  SwarmRunOptions resume_options;
  resume_options.threads = 2;
  int iterations_after_resume = 0;
  resume_options.progress = [&](const SwarmProgress&) { return ++iterations_after_resume > 0; };
  const SwarmSummary resumed = resume_swarm(dir / "killed.json", b.space(), b.f, resume_options);
  EXPECT_EQ(iterations_after_resume, 6);
  expect_same_run(full, resumed);
  std::printf("full: %s\nresumed: %s\n", full.brief_report().c_str(), resumed.brief_report().c_str());

  // A finished run's checkpoint resumes to the same summary without evaluating anything.
  int calls = 0;
  const SwarmSummary again = resume_swarm(dir / "full.json", b.space(), [&](const Eigen::VectorXd& x) {
    ++calls;
    return b.f(x);
  });
  EXPECT_EQ(calls, 0);
  expect_same_run(full, again);
}

TEST(ParticleSwarm, ResumeRejectsAnotherSpaceOrABrokenFileNamingTheField) {
  const auto& b = benchmark("booth_2d");
  const ScratchDir dir("swarm-resume-errors");
  SwarmSettings s;
  s.particles = 8;
  s.iterations = 3;
  SwarmRunOptions o;
  o.checkpoint = dir / "cp.json";
  (void)run_swarm(b.space(), b.f, s, o);

  auto message_of = [&](const ParameterSpace& space, const fs::path& file) {
    try {
      (void)resume_swarm(file, space, b.f);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const ParameterSpace other({{"", -10.0, 10.0, false}, {"", -10.0, 11.0, false}});
  EXPECT_NE(message_of(other, dir / "cp.json").find("space[1].upper"), std::string::npos)
      << message_of(other, dir / "cp.json");
  yarnfit::testing::write_file(dir / "broken.json", "{\"format\": ");
  EXPECT_NE(message_of(b.space(), dir / "broken.json").find("not valid JSON"), std::string::npos);
  std::string text = yarnfit::testing::read_file(dir / "cp.json");
  text.replace(text.find("\"velocity\""), 10, "\"velocitx\"");
  yarnfit::testing::write_file(dir / "edited.json", text);
  EXPECT_NE(message_of(b.space(), dir / "edited.json").find("velocity: missing"), std::string::npos)
      << message_of(b.space(), dir / "edited.json");
  EXPECT_NE(message_of(b.space(), dir / "absent.json").find("cannot open"), std::string::npos);
  // What the user does differs: a checkpoint that is not there (io), one that is broken (input).
  EXPECT_ERROR((void)resume_swarm(dir / "absent.json", b.space(), b.f), yarnfit::ErrorCategory::io);
  EXPECT_ERROR((void)resume_swarm(dir / "broken.json", b.space(), b.f), yarnfit::ErrorCategory::input);
}

TEST(ParticleSwarm, FailingEvaluationsArePenalisedAndReported) {
  const auto& b = benchmark("sphere_3d");  // minimiser (1, -2, 0.5)
  std::atomic<int> thrown{0}, nan{0};
  const Objective f = [&](const Eigen::VectorXd& x) {
    if (x[0] > 3.0) {
      ++thrown;
      throw std::runtime_error("no equilibrium for x0 = " + std::to_string(x[0]));
    }
    if (x[1] < -4.0) {
      ++nan;
      return std::numeric_limits<double>::quiet_NaN();
    }
    return b.f(x);
  };
  SwarmSettings s;
  s.seed = 3;
  const SwarmSummary r = run_swarm(b.space(), f, s);
  ASSERT_TRUE(r.usable());
  EXPECT_GT(thrown.load(), 0);
  EXPECT_GT(nan.load(), 0);
  EXPECT_EQ(r.failed, thrown + nan);
  int per_iteration = 0;
  for (const auto& h : r.history) per_iteration += h.failed;
  EXPECT_EQ(per_iteration, r.failed);
  EXPECT_EQ(r.failures.size(), std::min<std::size_t>(static_cast<std::size_t>(r.failed), 50));
  bool saw_throw = false, saw_nan = false;
  for (const auto& e : r.failures) {
    saw_throw |= e.message.find("objective threw: no equilibrium") != std::string::npos;
    saw_nan |= e.message.find("NaN") != std::string::npos;
    EXPECT_GE(e.particle, 0);
    EXPECT_TRUE(e.x[0] > 3.0 || e.x[1] < -4.0);
  }
  EXPECT_TRUE(saw_throw);
  EXPECT_TRUE(saw_nan);
  EXPECT_LE(r.best_point[0], 3.0);
  EXPECT_LT(r.best_value, 1e-2);
  std::printf("%s\n", r.brief_report().c_str());

  // Every evaluation failing is reported, not thrown, and gives no best point.
  s.particles = 4;
  s.iterations = 2;
  const SwarmSummary none = run_swarm(b.space(), [](const Eigen::VectorXd&) -> double { throw 17; }, s);
  EXPECT_FALSE(none.usable());
  EXPECT_EQ(none.best_point.size(), 0);
  EXPECT_EQ(none.failed, 8);
  EXPECT_TRUE(std::isinf(none.history.back().mean_value));
  EXPECT_NE(none.failures.front().message.find("not derived from std::exception"), std::string::npos);
  EXPECT_NE(none.brief_report().find("no successful evaluation"), std::string::npos);
}

// Without repulsion the particles pile up closer around the best point; the fading push
// keeps them further apart, and a wider radius more so.
TEST(ParticleSwarm, RepulsionKeepsParticlesApart) {
  const auto& b = benchmark("sphere_3d");
  SwarmSettings none, fading, wide;
  none.repulsion_strength = 0.0;
  wide.repulsion_radius = 0.5;
  const SwarmSummary r0 = run_swarm(b.space(), b.f, none);
  const SwarmSummary r1 = run_swarm(b.space(), b.f, fading);
  const SwarmSummary r2 = run_swarm(b.space(), b.f, wide);
  std::printf("iteration  nearest-neighbour distance: none / default / radius 0.5\n");
  for (std::size_t k = 0; k < r1.history.size(); ++k) {
    std::printf("%9d  %.4f / %.4f / %.4f\n", r1.history[k].iteration, r0.history[k].neighbour_distance,
                r1.history[k].neighbour_distance, r2.history[k].neighbour_distance);
  }
  std::printf("best value: %.3e / %.3e / %.3e\n", r0.best_value, r1.best_value, r2.best_value);
  EXPECT_EQ(r1.history[0].neighbour_distance, r0.history[0].neighbour_distance);  // same start
  EXPECT_GT(r1.history.back().neighbour_distance, r0.history.back().neighbour_distance);
  EXPECT_GT(r2.history.back().neighbour_distance, r1.history.back().neighbour_distance);
}

TEST(ParticleSwarm, InitialPointsStartTheFirstParticles) {
  const auto& b = benchmark("booth_2d");
  SwarmSettings s;
  s.particles = 8;
  s.iterations = 1;
  s.initial_points = {b.minimiser};
  const SwarmSummary r = run_swarm(b.space(), b.f, s);
  EXPECT_EQ(r.best_particle, 0);
  EXPECT_LT(r.best_value, 1e-20);
}

TEST(ParticleSwarm, InvalidSettingsNameTheField) {
  const auto& b = benchmark("booth_2d");
  auto message_of = [&](const SwarmSettings& s) {
    try {
      (void)run_swarm(b.space(), b.f, s);
    } catch (const yarnfit::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SwarmSettings s;
  s.particles = 1;
  EXPECT_NE(message_of(s).find("particles"), std::string::npos);
  s = {};
  s.iterations = 0;
  EXPECT_NE(message_of(s).find("iterations"), std::string::npos);
  s = {};
  s.max_velocity = 0.0;
  EXPECT_NE(message_of(s).find("max_velocity"), std::string::npos);
  s = {};
  s.inertia_end = std::nan("");
  EXPECT_NE(message_of(s).find("inertia_end"), std::string::npos);
  s = {};
  s.initial_points = {Eigen::Vector2d(0.0, 20.0)};
  EXPECT_NE(message_of(s).find("initial_points[0]: 'x[1]' (parameter 1) = 20 is outside"), std::string::npos)
      << message_of(s);
}

TEST(RandomStream, StandardEngineOwnDistributionsAndExactStateRoundTrip) {
  // The standard fixes mt19937_64's 10000th output for the default seed.
  std::mt19937_64 reference;
  reference.discard(9999);
  EXPECT_EQ(reference(), 9981545732273789042ull);

  RandomStream a(5489);
  for (int k = 0; k < 1000; ++k) {
    const double u = a.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ASSERT_LT(a.index(7), 7u);
  }
  RandomStream b(1);
  b.restore(a.state());
  for (int k = 0; k < 100; ++k) ASSERT_EQ(a.uniform(), b.uniform());
  EXPECT_ERROR(b.restore("12 not a state"), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::swarm
