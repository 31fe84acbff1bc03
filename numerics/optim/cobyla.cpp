#include "numerics/optim/cobyla.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::numerics {

namespace {

// Why the wrapper itself stopped NLopt (NLopt then reports NLOPT_FORCED_STOP).
enum class OwnStop { none, evaluations, time };

// Shared with NLopt's C callback; the callback must not throw through C code.
struct Context {
  const Objective& objective;
  const Eigen::VectorXd& lower;
  const Eigen::VectorXd& upper;
  const CobylaSettings& settings;
  nlopt_opt opt = nullptr;
  Clock::time_point start;
  CobylaSummary summary;
  Eigen::VectorXd best;
  // Range of the successful values seen, for the failure penalty.
  double worst_seen = -std::numeric_limits<double>::infinity();
  OwnStop own_stop = OwnStop::none;
};

// What COBYLA is told for a failed evaluation: worse than every value seen by at least the
// spread of the values seen (at least 1 and |worst|), so its model steers away from the
// failing region; finite, so its linear algebra stays clean.
double penalty(const Context& c) {
  if (!std::isfinite(c.worst_seen)) return 1e30;
  const double spread = std::max({1.0, std::abs(c.worst_seen), c.worst_seen - c.summary.best_value});
  return c.worst_seen + spread;
}

double callback(unsigned n, const double* u_raw, double* gradient, void* data) {
  (void)gradient;  // COBYLA is derivative-free: NLopt never asks for one
  auto& c = *static_cast<Context*>(data);
  CobylaSummary& s = c.summary;
  if (s.evaluations >= c.settings.max_evaluations) {
    c.own_stop = OwnStop::evaluations;
    nlopt_force_stop(c.opt);
    return penalty(c);
  }
  if (c.settings.max_seconds > 0.0 &&
      seconds_since(c.start) >= c.settings.max_seconds) {
    c.own_stop = OwnStop::time;
    nlopt_force_stop(c.opt);
    return penalty(c);
  }
  Eigen::VectorXd x(n);
  for (unsigned i = 0; i < n; ++i) x[i] = std::clamp(u_raw[i], c.lower[i], c.upper[i]);
  const Evaluation e = evaluate_guarded([&] { return c.objective(x); });
  const int index = s.evaluations++;
  if (index == 0) s.start_value = e.value;
  if (!e.ok) {
    ++s.failed;
    keep_failure(s.failures, c.settings.max_failures_kept, index, 0, -1, x, e.message);
    return penalty(c);
  }
  c.worst_seen = std::max(c.worst_seen, e.value);
  if (e.value < s.best_value) {
    s.best_value = e.value;
    c.best = x;
  }
  return e.value;
}

CobylaStatus status_of(nlopt_result r, OwnStop own) {
  switch (r) {
    case NLOPT_SUCCESS: return CobylaStatus::converged;
    case NLOPT_STOPVAL_REACHED: return CobylaStatus::stop_value;
    case NLOPT_FTOL_REACHED: return CobylaStatus::f_tolerance;
    case NLOPT_XTOL_REACHED: return CobylaStatus::x_tolerance;
    case NLOPT_MAXEVAL_REACHED: return CobylaStatus::max_evaluations;
    case NLOPT_MAXTIME_REACHED: return CobylaStatus::max_time;
    case NLOPT_ROUNDOFF_LIMITED: return CobylaStatus::roundoff_limited;
    case NLOPT_FORCED_STOP:
      if (own == OwnStop::evaluations) return CobylaStatus::max_evaluations;
      if (own == OwnStop::time) return CobylaStatus::max_time;
      return CobylaStatus::nlopt_failure;
    default: return CobylaStatus::nlopt_failure;
  }
}

void check(nlopt_result r, const char* what) {
  if (r < 0) throw Error(ErrorCategory::input, std::string("cobyla settings: NLopt rejected ") + what);
}

}  // namespace

Problems CobylaSettings::problems() const {
  Problems out;
  add_local_stopping_problems(out, max_evaluations, max_seconds, stop_value, max_failures_kept);
  if (!(initial_step > 0.0) || !std::isfinite(initial_step)) out.add_field("initial_step", "must be positive and finite");
  if (!(x_tolerance >= 0.0) || !std::isfinite(x_tolerance)) out.add_field("x_tolerance", "must be finite and ≥ 0");
  if (!(f_tolerance_relative >= 0.0) || std::isinf(f_tolerance_relative))
    out.add_field("f_tolerance_relative", "must be finite and ≥ 0");
  if (!(f_tolerance_absolute >= 0.0) || std::isinf(f_tolerance_absolute))
    out.add_field("f_tolerance_absolute", "must be finite and ≥ 0");
  return out;
}

const char* to_string(CobylaStatus status) {
  switch (status) {
    case CobylaStatus::converged: return "converged";
    case CobylaStatus::x_tolerance: return "converged: step below x_tolerance";
    case CobylaStatus::f_tolerance: return "converged: change of f below f_tolerance";
    case CobylaStatus::stop_value: return "reached stop_value";
    case CobylaStatus::max_evaluations: return "evaluation limit reached";
    case CobylaStatus::max_time: return "time limit reached";
    case CobylaStatus::roundoff_limited: return "round-off limited";
    case CobylaStatus::nlopt_failure: return "NLopt failure";
  }
  return "unknown";
}

bool is_converged(CobylaStatus status) {
  return status == CobylaStatus::converged || status == CobylaStatus::x_tolerance ||
         status == CobylaStatus::f_tolerance || status == CobylaStatus::stop_value;
}

bool CobylaSummary::usable() const { return std::isfinite(best_value); }

std::string CobylaSummary::brief_report() const {
  std::ostringstream s;
  s << "cobyla " << message << ": " << evaluations << " evaluations (" << failed << " failed), ";
  if (usable()) {
    s << "best " << best_value << " from " << start_value;
  } else {
    s << "no successful evaluation";
  }
  s << ", " << seconds << " s";
  return s.str();
}

CobylaSummary run_cobyla(const Objective& objective, const Eigen::VectorXd& start, const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& upper, const CobylaSettings& settings) {
  if (const Problems problems = settings.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "cobyla settings: " + problems.one_line());
  if (lower.size() != start.size() || upper.size() != start.size() || start.size() == 0)
    throw Error(ErrorCategory::input, "cobyla: start, lower and upper need the same, non-zero size");
  for (Eigen::Index i = 0; i < start.size(); ++i) {
    if (!(lower[i] <= upper[i]) || !std::isfinite(lower[i]) || !std::isfinite(upper[i]))
      throw Error(ErrorCategory::input,
                  "cobyla: bounds of coordinate " + std::to_string(i) + " are not a finite interval");
    if (!(start[i] >= lower[i] && start[i] <= upper[i]))
      throw Error(ErrorCategory::input, "cobyla start: coordinate " + std::to_string(i) + " lies outside its bounds");
  }
  Eigen::VectorXd u = start;

  const auto n = static_cast<unsigned>(start.size());
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LN_COBYLA, n), &nlopt_destroy);
  if (!opt) throw Error(ErrorCategory::system, "cobyla: NLopt could not create the optimiser (out of memory)");
  Context c{objective, lower, upper, settings, opt.get(), Clock::now(), {}, u, -std::numeric_limits<double>::infinity(),
            OwnStop::none};
  check(nlopt_set_lower_bounds(opt.get(), lower.data()), "the lower bounds");
  check(nlopt_set_upper_bounds(opt.get(), upper.data()), "the upper bounds");
  check(nlopt_set_min_objective(opt.get(), callback, &c), "the objective");
  check(nlopt_set_initial_step1(opt.get(), settings.initial_step), "initial_step");
  check(nlopt_set_xtol_abs1(opt.get(), settings.x_tolerance), "x_tolerance");
  check(nlopt_set_ftol_rel(opt.get(), settings.f_tolerance_relative), "f_tolerance_relative");
  check(nlopt_set_ftol_abs(opt.get(), settings.f_tolerance_absolute), "f_tolerance_absolute");
  check(nlopt_set_stopval(opt.get(), settings.stop_value), "stop_value");
  // NLopt's own limits as well as the callback's guards: NLopt then usually stops first and
  // reports the reason itself; the guards catch any overrun.
  check(nlopt_set_maxeval(opt.get(), settings.max_evaluations), "max_evaluations");
  if (settings.max_seconds > 0.0) check(nlopt_set_maxtime(opt.get(), settings.max_seconds), "max_seconds");

  double f_last = 0.0;
  const nlopt_result r = nlopt_optimize(opt.get(), u.data(), &f_last);

  CobylaSummary s = std::move(c.summary);
  s.status = status_of(r, c.own_stop);
  s.message = to_string(s.status);
  if (s.status == CobylaStatus::nlopt_failure) {
    const char* text = nlopt_get_errmsg(opt.get());
    s.message += " (nlopt_result " + std::to_string(static_cast<int>(r)) + (text ? std::string(": ") + text : "") + ")";
  }
  if (s.evaluations > 0 && s.failed == s.evaluations) s.message += "; every evaluation failed";
  // The best point seen (or the start when nothing succeeded), never NLopt's last iterate.
  s.best_point = c.best;
  s.seconds = seconds_since(c.start);
  return s;
}

}  // namespace yarnfit::numerics
