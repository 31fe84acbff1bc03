#include "yarn_fit/fit/local_step.hpp"

#include <omp.h>

#include <stdexcept>

#include "numerics/util/error.hpp"
#include "swarm/cobyla.hpp"

namespace yarnfit::yarn {

namespace {

// What the stencil and COBYLA summaries have in common.
template <class Summary>
void take_summary(const Summary& r, LocalStepSummary& out) {
  out.status = r.message;
  out.best_value = r.best_value;
  out.start_value = r.start_value;
  out.evaluations = r.evaluations;
  out.failed = r.failed;
  out.failures = r.failures;
  out.seconds = r.seconds;
  out.report = r.brief_report();
  if (r.usable()) out.best_point = r.best_point;
}

void gauss_newton(const YarnObjective& f, const swarm::ParameterSpace& space, const PointToParams& to_params,
                  const LocalStepSettings& s, const LocalProgress& progress, LocalStepSummary& out) {
  AlternationSettings as = s.alternation;
  as.fallback.max_evaluations = s.evaluations;
  as.fallback.initial_scale = s.initial_scale;
  as.fallback.min_scale = s.min_scale;
  as.fallback.threads = s.threads;
  out.alternation = run_alternation(f, space, to_params, out.start_point, as, progress);
  take_alternation(out);
}

}  // namespace

void take_alternation(LocalStepSummary& out) {
  const AlternationSummary& r = out.alternation;
  out.method = LocalMethod::gauss_newton;
  out.status = r.ok ? (r.converged ? "converged" : "stopped at its round limit") : r.message;
  if (r.fell_back) out.status += "; fell back to implicit filtering: " + r.fallback_reason;
  out.best_value = r.best_value;
  out.start_value = r.start_value;
  out.evaluations = r.evaluations;
  out.failed = r.failed_evaluations;
  out.seconds = r.seconds;
  out.report = r.brief_report();
  out.converged = r.converged;
  out.iterations = static_cast<int>(r.rounds.size());
  if (r.ok) out.best_point = r.best_point;
}

namespace {

void implicit_filtering(const YarnObjective& f, const swarm::ParameterSpace& space, const PointToParams& to_params,
                        const LocalStepSettings& s, const LocalProgress& progress, LocalStepSummary& out) {
  swarm::ImplicitFilteringSettings is;
  is.max_evaluations = s.evaluations;
  is.initial_scale = s.initial_scale;
  is.min_scale = s.min_scale;
  is.threads = s.threads;
  const swarm::ResidualObjective residuals = [&](const Eigen::VectorXd& x) {
    const ObjectiveResult r = f.evaluate(to_params(x));
    if (!r.ok) throw Error(ErrorCategory::solve, r.message);
    return residual_vector(r);
  };
  const swarm::ImplicitFilteringSummary r = swarm::run_implicit_filtering(
      space, residuals, out.start_point, is,
      [&](const swarm::ImplicitFilteringSummary& p) { if (progress) progress(p.evaluations, p.best_value); });
  take_summary(r, out);
  out.converged = r.status == swarm::ImplicitFilteringStatus::converged ||
                  r.status == swarm::ImplicitFilteringStatus::stop_value;
  out.iterations = static_cast<int>(r.history.size());
  out.final_scale = r.final_scale;
  out.history = r.history;
}

void cobyla(const YarnObjective& f, const swarm::ParameterSpace& space, const PointToParams& to_params,
            const LocalStepSettings& s, const LocalProgress& progress, LocalStepSummary& out) {
  swarm::CobylaSettings cs;
  cs.max_evaluations = s.evaluations;
  cs.initial_step = s.cobyla_initial_step;
  cs.x_tolerance = 1e-4;
  int step = 0;
  double best = std::numeric_limits<double>::infinity();
  const swarm::Objective g = [&](const Eigen::VectorXd& x) {
    const ObjectiveResult r = f.evaluate(to_params(x));
    if (!r.ok) throw Error(ErrorCategory::solve, r.message);
    best = std::min(best, r.value);
    if (progress) progress(++step, best);
    return r.value;
  };
  const swarm::CobylaSummary r = swarm::run_cobyla(space, g, out.start_point, cs);
  take_summary(r, out);
  out.converged = swarm::is_converged(r.status);
}

}  // namespace

const char* to_string(LocalMethod method) {
  switch (method) {
    case LocalMethod::gauss_newton: return "gauss-newton";
    case LocalMethod::implicit_filtering: return "implicit-filtering";
    case LocalMethod::cobyla: return "cobyla";
  }
  return "unknown";
}

std::optional<LocalMethod> local_method_from_string(std::string_view name) {
  for (const LocalMethod m : {LocalMethod::gauss_newton, LocalMethod::implicit_filtering, LocalMethod::cobyla})
    if (name == to_string(m)) return m;
  return std::nullopt;
}

LocalStepSummary run_local_step(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                const PointToParams& to_params, const Eigen::VectorXd& start,
                                const LocalStepSettings& settings, const LocalProgress& progress) {
  LocalStepSummary out;
  out.method = settings.method;
  out.ran = true;
  out.start_point = out.best_point = start;
  switch (settings.method) {
    case LocalMethod::gauss_newton: gauss_newton(objective, space, to_params, settings, progress, out); break;
    case LocalMethod::implicit_filtering:
      implicit_filtering(objective, space, to_params, settings, progress, out);
      break;
    case LocalMethod::cobyla: cobyla(objective, space, to_params, settings, progress, out); break;
  }
  return out;
}

}  // namespace yarnfit::yarn
