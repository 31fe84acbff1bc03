#include "yarn_fit/fit/global_search.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "numerics/util/error.hpp"
#include "yarn_fit/fit/fit_progress.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {

namespace {

using numerics::Clock;
using numerics::k_inf;

void report(const GlobalSearchInput& in, const std::string& stage, const char* step_name, int step, int steps,
            double best) {
  if (in.progress) in.progress(fit_progress(stage, step_name, step, steps, false, best, in.elapsed ? in.elapsed() : 0.0));
}

using Embed = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// One swarm stage over `space`, whose points `embed` maps into the full space.
GlobalStage run_stage(const std::string& name, const GlobalSearchInput& in, const swarm::ParameterSpace& space,
                      const Embed& embed, const SwarmStageSettings& s, std::uint64_t seed) {
  const auto start = Clock::now();
  GlobalStage stage;
  stage.name = name;
  const YarnObjective& objective = in.objective(s.samples, s.rest_rounds);
  swarm::SwarmSettings ss;
  ss.particles = s.particles;
  ss.iterations = s.iterations;
  ss.seed = seed;
  swarm::SwarmRunOptions run;
  run.threads = in.threads;
  if (!in.checkpoint.empty()) run.checkpoint = in.checkpoint.string() + "." + name;
  run.progress = [&](const swarm::SwarmProgress& p) {
    report(in, name, "iteration", p.record.iteration, p.iterations, p.record.best_value);
    return !in.keep_going || in.keep_going();
  };
  // A candidate stops once it cannot beat its particle's best (ParticleContext::cutoff): the
  // swarm runs as with exact values, and hopeless candidates end after their first samples.
  std::atomic<int> stopped{0};
  const swarm::ParticleObjective f = [&](const Eigen::VectorXd& x, const swarm::ParticleContext& c) {
    const ObjectiveResult r = objective.evaluate(in.to_params(embed(x)), in.cutoff ? c.cutoff : k_inf);
    if (!r.ok) throw Error(ErrorCategory::solve, r.message);
    if (r.lower_bound) ++stopped;
    return r.value;
  };
  const bool resuming = in.resume && !run.checkpoint.empty() && std::filesystem::exists(run.checkpoint);
  stage.swarm = resuming ? swarm::resume_swarm(run.checkpoint, space, f, run) : swarm::run_swarm(space, f, ss, run);
  stage.evaluations = stage.swarm.evaluations;
  stage.stopped = stopped.load();
  stage.best = stage.swarm.best_value;
  stage.seconds = numerics::seconds_since(start);
  return stage;
}

// The full space's parameters named in `names`, as a space of their own.
swarm::ParameterSpace subspace(const swarm::ParameterSpace& full, const std::vector<std::string>& names,
                               std::vector<int>& index) {
  std::vector<swarm::Parameter> p;
  for (const auto& name : names)
    for (int i = 0; i < full.dimension(); ++i)
      if (full.parameter(i).name == name) {
        p.push_back(full.parameter(i));
        index.push_back(i);
      }
  return swarm::ParameterSpace(std::move(p));
}

int index_of(const swarm::ParameterSpace& space, const std::string& name) {
  for (int i = 0; i < space.dimension(); ++i)
    if (space.parameter(i).name == name) return i;
  throw std::logic_error("global search: no parameter " + name);
}

// The distinct best of `candidates` (by value, ties in order), at most `count`, then each
// re-evaluated on the local samples, in parallel, best first.
std::vector<GlobalCandidate> rescore(const GlobalSearchInput& in, std::vector<GlobalCandidate> candidates,
                                     const StagedSearchSettings& s, GlobalStage& stage) {
  const auto start = Clock::now();
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const GlobalCandidate& a, const GlobalCandidate& b) { return a.value < b.value; });
  std::vector<GlobalCandidate> chosen;
  for (const auto& c : candidates) {
    if (!std::isfinite(c.value) || static_cast<int>(chosen.size()) >= s.rescored) continue;
    const Eigen::VectorXd u = in.space->to_unit(c.point);
    const bool near = std::any_of(chosen.begin(), chosen.end(), [&](const GlobalCandidate& o) {
      return (in.space->to_unit(o.point) - u).cwiseAbs().maxCoeff() < s.distinct;
    });
    if (!near) chosen.push_back(c);
  }
  const YarnObjective& local = in.objective(in.local_samples, 0);
  const int n = static_cast<int>(chosen.size());
  std::vector<double> value(static_cast<std::size_t>(n), k_inf);
  if (in.threads > 0) omp_set_num_threads(in.threads);
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < n; ++i) {
    const ObjectiveResult r = local.evaluate(in.to_params(chosen[static_cast<std::size_t>(i)].point));
    value[static_cast<std::size_t>(i)] = r.ok ? r.value : k_inf;
  }
  for (int i = 0; i < n; ++i) chosen[static_cast<std::size_t>(i)].value = value[static_cast<std::size_t>(i)];
  std::erase_if(chosen, [](const GlobalCandidate& c) { return !std::isfinite(c.value); });
  std::stable_sort(chosen.begin(), chosen.end(),
                   [](const GlobalCandidate& a, const GlobalCandidate& b) { return a.value < b.value; });
  stage.evaluations = n;
  stage.best = chosen.empty() ? k_inf : chosen.front().value;
  stage.seconds = numerics::seconds_since(start);
  report(in, "rescore", "candidate", n, n, stage.best);
  return chosen;
}

std::vector<GlobalCandidate> particle_bests(const swarm::SwarmSummary& swarm, const Embed& embed) {
  std::vector<GlobalCandidate> out;
  for (std::size_t i = 0; i < swarm.particle_best_values.size(); ++i)
    if (std::isfinite(swarm.particle_best_values[i]))
      out.push_back({embed(swarm.particle_best_points[i]), swarm.particle_best_values[i]});
  return out;
}

// True (and the result marked) when the last stage's swarm was asked to stop.
bool stopped(GlobalSearchResult& out) {
  out.stopped = out.stages.back().swarm.status == swarm::SwarmStatus::stopped;
  return out.stopped;
}

GlobalSearchResult finish(GlobalSearchResult out, Clock::time_point start) {
  for (const auto& s : out.stages) out.evaluations += s.evaluations;
  out.ok = !out.stopped && !out.starts.empty();
  if (!out.ok && !out.stopped && out.message.empty()) out.message = "every candidate of the global search failed";
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace

const char* to_string(GlobalMethod method) { return method == GlobalMethod::staged ? "staged" : "swarm"; }

std::optional<GlobalMethod> global_method_from_string(std::string_view name) {
  for (const GlobalMethod m : {GlobalMethod::staged, GlobalMethod::swarm})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

db::Problems StagedSearchSettings::problems() const {
  db::Problems out;
  for (const auto* s : {&contact, &all}) {
    const std::string which = s == &contact ? "contact." : "all.";
    if (s->particles < 2) out.add_field(which + "particles", "must be at least 2");
    if (s->iterations < 1) out.add_field(which + "iterations", "must be at least 1");
    if (s->samples < 2) out.add_field(which + "samples", "must be at least 2");
    if (s->rest_rounds < 0) out.add_field(which + "rest_rounds", "must not be negative");
  }
  if (!(r1_window > 0.0 && r1_window <= 0.5)) out.add_field("r1_window", "must be in (0, 0.5]");
  if (rescored < 1) out.add_field("rescored", "must be at least 1");
  if (!(distinct >= 0.0 && distinct < 1.0)) out.add_field("distinct", "must be in [0, 1)");
  if (starts < 1 || starts > rescored) out.add_field("starts", "must be in [1, rescored]");
  return out;
}

GlobalSearchResult run_staged_search(const GlobalSearchInput& in, const StagedSearchSettings& s) {
  if (const db::Problems problems = s.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "staged search: " + problems.one_line());
  const auto start = Clock::now();
  GlobalSearchResult out;
  const swarm::ParameterSpace& full = *in.space;
  const Eigen::VectorXd middle = full.from_unit(Eigen::VectorXd::Constant(full.dimension(), 0.5));

  // 1. R1 and kc1 alone, the others at the middle of their ranges.
  std::vector<int> contact_index;
  const swarm::ParameterSpace contact_space = subspace(full, {"R1", "kc1"}, contact_index);
  const Embed contact_embed = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd p = middle;
    for (std::size_t k = 0; k < contact_index.size(); ++k) p[contact_index[k]] = x[static_cast<Eigen::Index>(k)];
    return p;
  };
  out.stages.push_back(run_stage("contact", in, contact_space, contact_embed, s.contact, in.seed));
  if (stopped(out)) return finish(out, start);
  const swarm::SwarmSummary& first = out.stages.back().swarm;
  if (!first.usable()) {
    out.message = "every contact-stage candidate failed: " +
                  (first.failures.empty() ? std::string("no reason kept") : first.failures.front().message);
    return finish(out, start);
  }
  const Eigen::VectorXd pinned = contact_embed(first.best_point);

  // 2. Every parameter, R1 within the window around stage 1's.
  const int r1 = index_of(full, "R1");
  std::vector<swarm::Parameter> narrowed = full.parameters();
  narrowed[static_cast<std::size_t>(r1)].lower = std::max(full.parameter(r1).lower, pinned[r1] * (1.0 - s.r1_window));
  narrowed[static_cast<std::size_t>(r1)].upper = std::min(full.parameter(r1).upper, pinned[r1] * (1.0 + s.r1_window));
  const swarm::ParameterSpace all_space(narrowed);
  const Embed identity = [](const Eigen::VectorXd& x) { return x; };
  out.stages.push_back(run_stage("all", in, all_space, identity, s.all, in.seed + 1));
  if (stopped(out)) return finish(out, start);

  // 3. The distinct best of both, on the local samples.
  GlobalStage rescored;
  rescored.name = "rescore";
  if (in.rescored) {  // from the checkpoint of an earlier run of this fit
    out.starts = *in.rescored;
    rescored.best = out.starts.empty() ? k_inf : out.starts.front().value;
  } else {
    std::vector<GlobalCandidate> candidates = particle_bests(out.stages.back().swarm, identity);
    candidates.push_back({pinned, out.stages.front().swarm.best_value});
    out.starts = rescore(in, std::move(candidates), s, rescored);
    if (in.on_rescored) in.on_rescored(out.starts);
  }
  out.stages.push_back(rescored);
  if (static_cast<int>(out.starts.size()) > s.starts) out.starts.resize(static_cast<std::size_t>(s.starts));
  return finish(out, start);
}

GlobalSearchResult run_swarm_search(const GlobalSearchInput& in, const SwarmStageSettings& s) {
  const auto start = Clock::now();
  GlobalSearchResult out;
  const Embed identity = [](const Eigen::VectorXd& x) { return x; };
  out.stages.push_back(run_stage("swarm", in, *in.space, identity, s, in.seed));
  if (stopped(out)) return finish(out, start);
  const swarm::SwarmSummary& sw = out.stages.back().swarm;
  if (sw.usable()) out.starts.push_back({sw.best_point, sw.best_value});
  else
    out.message = "every swarm candidate failed: " +
                  (sw.failures.empty() ? std::string("no reason kept") : sw.failures.front().message);
  return finish(out, start);
}

}  // namespace yarnfit::yarn
