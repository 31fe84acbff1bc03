#include "swarm/particle_swarm.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "swarm/random.hpp"
#include "swarm/swarm_state.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::swarm {

namespace {

using numerics::k_inf;

using numerics::Clock;

// Inertia of the move into iteration `iteration` (2 ≤ iteration ≤ iterations): linear from
// inertia_start on the first move to inertia_end on the last.
double inertia_for(const SwarmSettings& s, int iteration) {
  const int moves = s.iterations - 1;
  const double t = moves > 1 ? static_cast<double>(iteration - 2) / (moves - 1) : 0.0;
  return s.inertia_start + (s.inertia_end - s.inertia_start) * t;
}

// The start state: Latin hypercube positions, random velocities, no bests yet.
detail::SwarmState start_state(const ParameterSpace& space, const SwarmSettings& s, RandomStream& rng) {
  const int d = space.dimension();
  const int n = s.particles;
  detail::SwarmState st;
  st.settings = s;
  st.position.resize(d, n);
  std::vector<int> slab(static_cast<std::size_t>(n));
  for (int c = 0; c < d; ++c) {
    std::iota(slab.begin(), slab.end(), 0);
    for (int i = n - 1; i > 0; --i) {  // Fisher–Yates
      const auto j = static_cast<int>(rng.index(static_cast<std::uint64_t>(i) + 1));
      std::swap(slab[static_cast<std::size_t>(i)], slab[static_cast<std::size_t>(j)]);
    }
    for (int i = 0; i < n; ++i) st.position(c, i) = (slab[static_cast<std::size_t>(i)] + rng.uniform()) / n;
  }
  st.velocity.resize(d, n);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < d; ++c) st.velocity(c, i) = rng.uniform(-s.max_velocity, s.max_velocity);
  }
  // Given start points replace random ones after all draws, so they do not shift the stream.
  for (std::size_t k = 0; k < s.initial_points.size(); ++k) {
    try {
      st.position.col(static_cast<Eigen::Index>(k)) = space.to_unit(s.initial_points[k]);
    } catch (const Error& e) {
      throw with_context("swarm settings: initial_points[" + std::to_string(k) + "]: ", e);
    }
  }
  st.best_position = st.position;
  st.best_value = Eigen::VectorXd::Constant(n, k_inf);
  st.global_best = Eigen::VectorXd::Constant(d, 0.5);
  st.summary.settings = s;
  st.random_state = rng.state();
  return st;
}

// Repulsion a_i of every particle (formula in particle_swarm.hpp), d × N.
Eigen::MatrixXd repulsion(const SwarmSettings& s, const Eigen::MatrixXd& x) {
  const Eigen::Index d = x.rows();
  const Eigen::Index n = x.cols();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(d, n);
  if (s.repulsion_strength == 0.0 || s.repulsion_radius == 0.0) return a;
  const double r = s.repulsion_radius * std::pow(static_cast<double>(n), -1.0 / static_cast<double>(d));
  const double kick = s.repulsion_strength * r;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const Eigen::VectorXd diff = x.col(i) - x.col(j);
      const double dist = diff.norm();
      // Coincident particles have no direction to push along; their different random pulls
      // separate them in the next move.
      if (dist <= 0.0 || dist >= r) continue;
      const double fall = 1.0 - dist / r;
      const Eigen::VectorXd push = (kick * fall * fall / dist) * diff;
      a.col(i) += push;
      a.col(j) -= push;
    }
  }
  return a;
}

// Mean over particles of the distance to the nearest other particle (unit cube).
double mean_neighbour_distance(const Eigen::MatrixXd& x) {
  const Eigen::Index n = x.cols();
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(n, k_inf);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const double d = (x.col(i) - x.col(j)).norm();
      nearest[i] = std::min(nearest[i], d);
      nearest[j] = std::min(nearest[j], d);
    }
  }
  return nearest.mean();
}

// Moves every particle into iteration `iteration` (formula in particle_swarm.hpp). Random
// numbers are drawn in particle order, two per coordinate, whether or not they are used.
void move(detail::SwarmState& st, RandomStream& rng, double w) {
  const SwarmSettings& s = st.settings;
  const bool has_best = st.summary.usable();
  const double fade = s.inertia_start > 0.0 ? w / s.inertia_start : 1.0;
  const Eigen::MatrixXd a = fade * repulsion(s, st.position);
  for (Eigen::Index i = 0; i < st.position.cols(); ++i) {
    for (Eigen::Index c = 0; c < st.position.rows(); ++c) {
      const double r1 = rng.uniform();
      const double r2 = rng.uniform();
      const double x = st.position(c, i);
      double v = w * st.velocity(c, i) + s.cognitive * r1 * (st.best_position(c, i) - x) + a(c, i);
      if (has_best) v += s.social * r2 * (st.global_best[c] - x);
      v = std::clamp(v, -s.max_velocity, s.max_velocity);
      double next = x + v;
      if (next < 0.0 || next > 1.0) {
        next = std::clamp(next, 0.0, 1.0);
        v = 0.0;
      }
      st.position(c, i) = next;
      st.velocity(c, i) = v;
    }
  }
}

// Evaluates every particle (in parallel), then updates bests, counters and the history
// serially in particle order.
void evaluate(detail::SwarmState& st, const ParameterSpace& space, const ParticleObjective& objective,
              const SwarmRunOptions& options, int iteration, double inertia) {
  const auto start = Clock::now();
  const int n = st.settings.particles;
  std::vector<Eigen::VectorXd> points(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) points[static_cast<std::size_t>(i)] = space.from_unit(st.position.col(i));
  std::vector<Evaluation> results(static_cast<std::size_t>(n));
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ParticleContext context{iteration, i, st.best_value[i]};
    results[k] = evaluate_guarded([&] { return objective(points[k], context); });
  }

  SwarmSummary& sum = st.summary;
  IterationRecord rec;
  rec.iteration = iteration;
  rec.inertia = inertia;
  double total = 0.0;
  int succeeded = 0;
  for (int i = 0; i < n; ++i) {
    const auto& e = results[static_cast<std::size_t>(i)];
    const int evaluation = sum.evaluations++;
    if (!e.ok) {
      ++rec.failed;
      ++sum.failed;
      keep_failure(sum.failures, options.max_failures_kept, evaluation, iteration, i, points[static_cast<std::size_t>(i)],
                   e.message);
      continue;
    }
    total += e.value;
    ++succeeded;
    rec.iteration_best = std::min(rec.iteration_best, e.value);
    if (e.value < st.best_value[i]) {
      st.best_value[i] = e.value;
      st.best_position.col(i) = st.position.col(i);
    }
    if (e.value < sum.best_value) {
      sum.best_value = e.value;
      sum.best_iteration = iteration;
      sum.best_particle = i;
      st.global_best = st.position.col(i);
    }
  }
  if (succeeded > 0) rec.mean_value = total / succeeded;
  rec.neighbour_distance = mean_neighbour_distance(st.position);
  rec.best_value = sum.best_value;
  if (sum.usable()) sum.best_point = space.from_unit(st.global_best);
  rec.seconds = numerics::seconds_since(start);
  sum.history.push_back(rec);
}

// Runs the remaining iterations of `st`.
SwarmSummary continue_run(detail::SwarmState st, const ParameterSpace& space, const ParticleObjective& objective,
                          const SwarmRunOptions& options, const std::filesystem::path& checkpoint) {
  if (options.threads < 0) throw Error(ErrorCategory::input, "swarm run options: threads must be ≥ 0");
  if (options.max_failures_kept < 0)
    throw Error(ErrorCategory::input, "swarm run options: max_failures_kept must be ≥ 0");
  RandomStream rng(0);
  rng.restore(st.random_state);
  const auto run_start = Clock::now();
  const double seconds_before = st.summary.seconds;
  const int first = st.iterations_done;
  st.summary.status = SwarmStatus::completed;
  while (st.iterations_done < st.settings.iterations) {
    const int iteration = st.iterations_done + 1;
    double w = 0.0;
    if (iteration > 1) {
      w = inertia_for(st.settings, iteration);
      move(st, rng, w);
    }
    evaluate(st, space, objective, options, iteration, w);
    st.iterations_done = iteration;
    st.random_state = rng.state();
    st.summary.seconds = seconds_before + numerics::seconds_since(run_start);
    if (!checkpoint.empty()) detail::write_checkpoint(checkpoint, space, st);
    if (options.progress) {
      const double per_iteration = numerics::seconds_since(run_start) / (iteration - first);
      const SwarmProgress p{st.summary.history.back(), st.settings.iterations, st.summary.best_point,
                            st.summary.evaluations, st.summary.failed, st.summary.seconds,
                            per_iteration * (st.settings.iterations - iteration)};
      if (!options.progress(p) && iteration < st.settings.iterations) {
        st.summary.status = SwarmStatus::stopped;
        break;
      }
    }
  }
  st.summary.particle_best_points.clear();
  st.summary.particle_best_values.clear();
  for (Eigen::Index i = 0; i < st.best_value.size(); ++i) {
    const bool found = std::isfinite(st.best_value[i]);
    st.summary.particle_best_points.push_back(found ? space.from_unit(st.best_position.col(i)) : Eigen::VectorXd());
    st.summary.particle_best_values.push_back(st.best_value[i]);
  }
  return st.summary;
}

ParticleObjective ignore_context(const Objective& f) {
  return [f](const Eigen::VectorXd& x, const ParticleContext&) { return f(x); };
}

}  // namespace

numerics::Problems SwarmSettings::problems() const {
  numerics::Problems out;
  const auto finite_at_least = [](double v, double lo) { return std::isfinite(v) && v >= lo; };
  const auto must_be_finite = [&](const char* field, double v) {
    if (!finite_at_least(v, 0.0)) out.add_field(field, "must be finite and ≥ 0");
  };
  if (particles < 2) out.add_field("particles", "must be at least 2 (got " + std::to_string(particles) + ")");
  if (iterations < 1) out.add_field("iterations", "must be at least 1 (got " + std::to_string(iterations) + ")");
  must_be_finite("inertia_start", inertia_start);
  must_be_finite("inertia_end", inertia_end);
  must_be_finite("cognitive", cognitive);
  must_be_finite("social", social);
  if (!(max_velocity > 0.0 && max_velocity <= 1.0)) out.add_field("max_velocity", "must be in (0, 1] (fraction of the range)");
  must_be_finite("repulsion_radius", repulsion_radius);
  must_be_finite("repulsion_strength", repulsion_strength);
  if (initial_points.size() > static_cast<std::size_t>(particles))
    out.add_field("initial_points", "has " + std::to_string(initial_points.size()) + " points, more than particles (" +
                                        std::to_string(particles) + ")");
  return out;
}

const char* to_string(SwarmStatus status) {
  switch (status) {
    case SwarmStatus::completed: return "completed";
    case SwarmStatus::stopped: return "stopped by the progress callback";
  }
  return "unknown";
}

bool SwarmSummary::usable() const { return std::isfinite(best_value); }

std::string SwarmSummary::brief_report() const {
  std::ostringstream s;
  s << "swarm " << to_string(status) << ": " << history.size() << "/" << settings.iterations << " iterations, "
    << evaluations << " evaluations (" << failed << " failed), ";
  if (usable()) {
    s << "best " << best_value << " (iteration " << best_iteration << ", particle " << best_particle << ")";
  } else {
    s << "no successful evaluation";
  }
  s << ", " << seconds << " s";
  return s.str();
}

SwarmSummary run_swarm(const ParameterSpace& space, const ParticleObjective& objective, const SwarmSettings& settings,
                       const SwarmRunOptions& options) {
  if (const numerics::Problems problems = settings.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "swarm settings: " + problems.one_line());
  RandomStream rng(settings.seed);
  return continue_run(start_state(space, settings, rng), space, objective, options, options.checkpoint);
}

SwarmSummary run_swarm(const ParameterSpace& space, const Objective& objective, const SwarmSettings& settings,
                       const SwarmRunOptions& options) {
  return run_swarm(space, ignore_context(objective), settings, options);
}

SwarmSummary resume_swarm(const std::filesystem::path& checkpoint, const ParameterSpace& space,
                          const ParticleObjective& objective, const SwarmRunOptions& options) {
  detail::SwarmState st = detail::read_checkpoint(checkpoint, space);
  try {
    RandomStream(0).restore(st.random_state);
  } catch (const Error& e) {
    throw with_context("checkpoint " + checkpoint.string() + ": random_state: ", e);
  }
  return continue_run(std::move(st), space, objective, options,
                      options.checkpoint.empty() ? checkpoint : options.checkpoint);
}

SwarmSummary resume_swarm(const std::filesystem::path& checkpoint, const ParameterSpace& space,
                          const Objective& objective, const SwarmRunOptions& options) {
  return resume_swarm(checkpoint, space, ignore_context(objective), options);
}

}  // namespace yarnfit::swarm
