#include "numerics/newton/newton_solver.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "numerics/util/clock.hpp"
#include "numerics/util/format.hpp"

namespace yarnfit::numerics {

namespace {

double infinity_norm(const Eigen::VectorXd& v) { return v.size() > 0 ? v.lpNorm<Eigen::Infinity>() : 0.0; }

}  // namespace

NewtonPolicy NewtonPolicy::shell() { return {}; }

NewtonPolicy NewtonPolicy::shell_unprojected() {
  NewtonPolicy p = shell();
  p.project_psd = false;
  return p;
}

NewtonPolicy NewtonPolicy::yarn_tile() {
  NewtonPolicy p;
  // The exact Hessian gives quadratic convergence near equilibrium, where it is positive
  // definite on the constraint space; the per-element PSD projection is the safeguard when
  // it is not (far from equilibrium, or at an unstable state). Projected-only Newton
  // converges linearly when some elements are indefinite at the solution (edges in
  // compression, barrier curvature). Every iteration starts from the exact Hessian.
  p.project_psd = true;
  p.exact_hessian_first = true;
  p.remember_projection = false;
  p.project_after_failed_line_search = false;
  // An indefinite exact Hessian is first shifted (Levenberg): the shifted step still follows
  // the directions of negative curvature out of a saddle, where the per-element projection
  // would discard them and creep, converging linearly. A shift beyond 1e-3 of the mean
  // diagonal falls back to the projection, which takes longer steps far from equilibrium
  // (the limit chosen by measurement: docs/slack-tiles.md).
  p.shift_initial = 1e-8;
  p.exact_shift_limit = 1e-3;
  p.exact_shift_growth = 10.0;
  p.exact_shift_floor = 1e-6;
  p.shift_growth = 100.0;
  p.shift_max = 1e2;
  p.fail_beyond_shift_max = false;
  p.max_failed_attempts = 8;
  p.shift_shrink = 0.25;
  p.shift_floor = 1e-10;
  p.limited_step_growth = 4.0;
  p.shift_past_nonpositive_diagonal = false;
  // The tile's Hessian is indefinite along a yarn sliding through itself against the tile,
  // which the constraints forbid: positive definite on them is enough for the exact step.
  p.accept_definite_on_constraints = true;
  p.precision_floor = PrecisionFloor::predicted_decrease;
  p.floor_residual_factor = 1.0;
  p.roundoff_converged_factor = 1e3;
  return p;
}

void NewtonPolicy::add_problems(Problems& out, const std::string& prefix) const {
  const auto bad = [&](const char* field, const char* m) { out.add_field(prefix + field, m); };
  const auto finite_at_least = [](double v, double lo) { return std::isfinite(v) && v >= lo; };
  if (max_line_search_steps < 1) bad("max_line_search_steps", "must be ≥ 1");
  if (!(armijo > 0.0 && armijo < 0.5)) bad("armijo", "must be in (0, 0.5)");
  if (!finite_at_least(shift_initial, 0.0)) bad("shift_initial", "must be finite and ≥ 0");
  if (!(shift_start > 0.0) || !std::isfinite(shift_start)) bad("shift_start", "must be positive and finite");
  if (!(shift_growth > 1.0) || !std::isfinite(shift_growth)) bad("shift_growth", "must be > 1 and finite");
  if (!(shift_shrink > 0.0 && shift_shrink < 1.0)) bad("shift_shrink", "must be in (0, 1)");
  if (!(shift_max >= shift_start) || !std::isfinite(shift_max)) bad("shift_max", "must be finite and ≥ shift_start");
  if (!finite_at_least(shift_floor, 0.0) || shift_floor > shift_max) bad("shift_floor", "must be in [0, shift_max]");
  if (max_failed_attempts < 0) bad("max_failed_attempts", "must be ≥ 0 (0: no limit)");
  if (!finite_at_least(exact_shift_limit, 0.0)) bad("exact_shift_limit", "must be finite and ≥ 0 (0: project at once)");
  if (!(exact_shift_growth > 1.0) || !std::isfinite(exact_shift_growth)) bad("exact_shift_growth", "must be > 1 and finite");
  if (!finite_at_least(exact_shift_floor, 0.0)) bad("exact_shift_floor", "must be finite and ≥ 0");
  if (!finite_at_least(limited_step_growth, 1.0)) bad("limited_step_growth", "must be finite and ≥ 1");
  if (!(floor_residual_factor > 0.0 && floor_residual_factor <= 1.0)) bad("floor_residual_factor", "must be in (0, 1]");
  if (!finite_at_least(roundoff_converged_factor, 0.0)) bad("roundoff_converged_factor", "must be finite and ≥ 0");
}

NewtonOptions NewtonOptions::for_shell() { return {}; }

NewtonOptions NewtonOptions::for_shell_unprojected() {
  NewtonOptions o;
  o.policy = NewtonPolicy::shell_unprojected();
  return o;
}

NewtonOptions NewtonOptions::for_yarn_tile() {
  NewtonOptions o;
  o.policy = NewtonPolicy::yarn_tile();
  return o;
}

Problems NewtonOptions::problems() const {
  Problems out;
  add_problems(out, "NewtonOptions.");
  return out;
}

void NewtonOptions::add_problems(Problems& out, const std::string& prefix) const {
  const auto bad = [&](const char* field, const char* m) { out.add_field(prefix + field, m); };
  const auto finite_at_least = [](double v, double lo) { return std::isfinite(v) && v >= lo; };
  if (max_iterations < 0) bad("max_iterations", "must be ≥ 0");
  if (!finite_at_least(tolerance, 0.0)) bad("tolerance", "must be finite and ≥ 0");
  if (!finite_at_least(time_limit_s, 0.0)) bad("time_limit_s", "must be finite and ≥ 0 (0: none)");
  if (!finite_at_least(loose_tolerance, 0.0)) bad("loose_tolerance", "must be finite and ≥ 0 (0: off)");
  if (loose_after < 0) bad("loose_after", "must be ≥ 0");
  if (!finite_at_least(readout_tolerance, 0.0)) bad("readout_tolerance", "must be finite and ≥ 0 (0: off)");
  if (readout_steps < 1) bad("readout_steps", "must be ≥ 1");
  policy.add_problems(out, prefix + "policy.");
}

const char* to_string(NewtonStatus status) {
  switch (status) {
    case NewtonStatus::converged: return "converged";
    case NewtonStatus::converged_loosely: return "converged_loosely";
    case NewtonStatus::converged_readout: return "converged_readout";
    case NewtonStatus::max_iterations: return "max_iterations";
    case NewtonStatus::line_search_failed: return "line_search_failed";
    case NewtonStatus::invalid_start: return "invalid_start";
    case NewtonStatus::linear_solver_failed: return "linear_solver_failed";
    case NewtonStatus::non_finite: return "non_finite";
    case NewtonStatus::time_limit: return "time_limit";
  }
  return "unknown";
}

std::string NewtonSummary::brief() const {
  std::ostringstream out;
  out << "Newton " << to_string(status) << ": " << iterations << " iterations, residual "
      << format_number(residual) << ", E " << format_number(energy) << ", " << format_number(seconds * 1e3) << " ms";
  if (projected_steps > 0) out << ", " << projected_steps << " projected";
  if (regularised_steps > 0) out << ", " << regularised_steps << " regularised";
  if (continuation_steps > 0 || cut_backs > 0) {
    out << ", " << continuation_steps << " load steps, " << cut_backs << " cut-backs, lambda "
        << format_number(lambda);
  }
  if (!converged() && !message.empty()) out << " (" << message << ")";
  return out.str();
}

Eigen::VectorXd projected_gradient(const Eigen::MatrixXd* c, const Eigen::VectorXd& gradient) {
  if (c == nullptr || c->rows() == 0) return gradient;
  const Eigen::MatrixXd cct = *c * c->transpose();
  const Eigen::VectorXd lambda = cct.ldlt().solve(*c * gradient);
  return gradient - c->transpose() * lambda;
}

NewtonSummary solve_newton(NewtonProblem& problem, Eigen::VectorXd& x, const NewtonOptions& options,
                           ShiftedLdlt* workspace) {
  const auto start = Clock::now();
  const auto elapsed = [&] { return seconds_since(start); };
  if (const Problems problems = options.problems(); !problems.empty())
    throw std::invalid_argument("solve_newton: " + problems.one_line());
  const NewtonPolicy& policy = options.policy;
  std::string why;

  NewtonSummary summary;
  summary.tolerance = options.tolerance;
  const int n = problem.size();
  if (x.size() != n) x = Eigen::VectorXd::Zero(n);
  const Eigen::MatrixXd* c = problem.constraints();
  if (c != nullptr && c->rows() == 0) c = nullptr;
  Eigen::LDLT<Eigen::MatrixXd> cct_ldlt;
  if (c != nullptr) {
    // Project the start onto C x = 0 (a warm start from another state may drift).
    cct_ldlt.compute(*c * c->transpose());
    x -= c->transpose() * cct_ldlt.solve(*c * x);
  }
  // The residual the stopping test measures; with C the projected gradient of A.2.3.
  const auto residual_of = [&](const Eigen::VectorXd& gradient) {
    if (c == nullptr) return infinity_norm(gradient);
    return infinity_norm(gradient - c->transpose() * cct_ldlt.solve(*c * gradient));
  };
  ShiftedLdlt own_factor;
  ShiftedLdlt& factor = workspace != nullptr ? *workspace : own_factor;
  const int analyses_before = factor.analyses();
  const auto finish = [&](NewtonStatus status, std::string message) {
    summary.status = status;
    summary.message = std::move(message);
    summary.analyses = factor.analyses() - analyses_before;
    summary.seconds = elapsed();
    return summary;
  };

  problem.prepare(x);
  Eigen::VectorXd gradient;
  double energy = problem.energy_gradient(x, gradient);
  summary.energy = energy;
  if (!std::isfinite(energy)) {
    summary.residual = summary.initial_residual = std::numeric_limits<double>::quiet_NaN();
    const std::string what = problem.describe_invalid_energy(x);
    return finish(NewtonStatus::invalid_start, "the start state's energy is not finite" + (what.empty() ? "" : ": " + what));
  }
  double residual = gradient.allFinite() ? residual_of(gradient) : std::numeric_limits<double>::quiet_NaN();
  summary.initial_residual = residual;

  Triplets triplets;
  Eigen::VectorXd trial(n), trial_gradient;
  double shift = policy.shift_initial;  // relative shift μ
  bool exact_failed_last = false;        // remember_projection: the exact Hessian failed last iteration
  int nan_trials = 0;                    // trial energies that were NaN (a term breaking its contract)
  const bool predicted_floor = policy.precision_floor == PrecisionFloor::predicted_decrease;
  // The read-out test: the read-out at x, and how many accepted steps in a row changed it by
  // at most a quarter of the tolerance.
  Eigen::VectorXd readout, next_readout;
  const bool watch_readout = options.readout_tolerance > 0.0 && problem.readout(x, readout);
  int quiet_steps = 0;
  bool last_step_full = false;

  while (true) {
    if (!gradient.allFinite()) {
      const std::string what = problem.describe_invalid_gradient(x);
      return finish(NewtonStatus::non_finite,
                    "the gradient is not finite at a state of finite energy" + (what.empty() ? "" : " (from " + what + ")"));
    }
    summary.residual = residual;
    summary.energy = energy;
    if (residual <= options.tolerance) return finish(NewtonStatus::converged, "");
    if (watch_readout && quiet_steps >= options.readout_steps && last_step_full)
      return finish(NewtonStatus::converged_readout,
                    "the read-out changed by at most " + format_number(options.readout_tolerance / 4.0) + " in each of the last " +
                        std::to_string(quiet_steps) + " steps (residual " + format_number(residual) + " > tolerance " +
                        format_number(options.tolerance) + ")");
    if (summary.iterations >= options.max_iterations)
      return finish(NewtonStatus::max_iterations, "stopped after " + std::to_string(summary.iterations) +
                                                      " iterations: residual " + format_number(residual) +
                                                      " > tolerance " + format_number(options.tolerance));
    if (summary.iterations >= options.loose_after && residual <= options.loose_tolerance)
      return finish(NewtonStatus::converged_loosely,
                    "stopped after " + std::to_string(summary.iterations) +
                        " iterations within the loose tolerance (residual " + format_number(residual) +
                        ", loose tolerance " + format_number(options.loose_tolerance) + ")");
    if (options.time_limit_s > 0.0 && elapsed() > options.time_limit_s)
      return finish(NewtonStatus::time_limit, "time limit reached before convergence");

    // The exact Hessian first (the true Newton step, and no per-element eigen-decompositions)
    // unless the options or the last iteration say otherwise; the projection when it fails.
    const bool skip_exact = policy.project_psd && policy.exact_hessian_first && policy.remember_projection &&
                            exact_failed_last;
    bool exact = !policy.project_psd || (policy.exact_hessian_first && !skip_exact);
    const auto assemble = [&]() {
      triplets.clear();
      ++summary.assemblies;
      if (!problem.hessian(x, !exact, triplets, &why)) return false;
      factor.assemble(n, triplets);
      if (policy.shift_past_nonpositive_diagonal) {
        const double lowest = factor.relative_min_diagonal();
        if (lowest <= 0.0) shift = std::max(shift, policy.shift_start - lowest);
      }
      return true;
    };
    if (!assemble()) return finish(NewtonStatus::non_finite, why);

    bool accepted = false;
    bool floor_step = false;  // accepted at the precision floor without a line search
    bool unshifted_at_floor = false;
    bool limited = false;
    bool factorised_once = false;
    int failed_attempts = 0;
    std::string last_failure;
    // After a failure: the projection replaces the exact Hessian (true), or the shift grows;
    // false when the solve must stop (the summary is then final).
    std::optional<NewtonSummary> stopped;
    const auto switch_to_projection = [&]() {
      exact = false;
      exact_failed_last = true;
      if (!assemble()) {
        stopped = finish(NewtonStatus::non_finite, why);
        return false;
      }
      return true;
    };
    const auto grow_shift = [&]() {
      ++failed_attempts;
      shift = shift == 0.0 ? policy.shift_start : shift * policy.shift_growth;
      if (shift <= policy.shift_max) return true;
      if (!policy.fail_beyond_shift_max) {
        shift = policy.shift_max;
        return true;
      }
      std::string message = last_failure + " at every shift up to " + format_number(policy.shift_max) +
                            " x mean |diag H|; residual " + format_number(residual);
      if (nan_trials > 0)
        message += "; " + std::to_string(nan_trials) + " trial energies were NaN (a term breaks its contract)";
      stopped = finish(factorised_once ? NewtonStatus::line_search_failed : NewtonStatus::linear_solver_failed, message);
      return false;
    };

    while (!accepted) {
      if (policy.max_failed_attempts > 0 && failed_attempts >= policy.max_failed_attempts) break;
      ++summary.factorisations;
      // K⁻¹Cᵀ, kept when the inertia test computed it for this factorisation.
      Eigen::MatrixXd kc;
      const bool definite = factor.factorise(shift) ||
                            (exact && c != nullptr && policy.accept_definite_on_constraints &&
                             positive_definite_on_constraints(factor, *c, &kc));
      if (!definite) {
        last_failure = "the shifted Hessian was not positive definite";
        if (exact && shift < policy.exact_shift_limit) {
          shift = std::max(shift * policy.exact_shift_growth, policy.exact_shift_floor);
          continue;
        }
        if (exact && policy.project_psd) {
          if (!switch_to_projection()) return *stopped;
          continue;
        }
        if (!grow_shift()) return *stopped;
        continue;
      }
      factorised_once = true;
      const Eigen::VectorXd d0 = factor.solve(Eigen::VectorXd(-gradient));
      Eigen::VectorXd step = d0;
      if (c != nullptr) {
        // The KKT step of (3.32) by the Schur complement on the constraint rows.
        const Eigen::MatrixXd y = kc.size() > 0 ? kc : factor.solve(Eigen::MatrixXd(c->transpose()));
        const Eigen::MatrixXd s = *c * y;
        const Eigen::VectorXd lambda = s.ldlt().solve(*c * d0);
        step = d0 - y * lambda;
        // x is kept exactly feasible, so the step must be too: remove the round-off part of
        // C δ, which would otherwise dominate the slope once the residual is tiny.
        step -= c->transpose() * cct_ldlt.solve(*c * step);
      }
      const auto after_failed_step = [&]() {
        if (exact && policy.project_psd && policy.project_after_failed_line_search) return switch_to_projection();
        return grow_shift();
      };
      if (!step.allFinite()) {
        last_failure = "the Newton step was not finite";
        if (!after_failed_step()) return *stopped;
        continue;
      }
      const NewtonProblem::StepBound bound = problem.max_step(x, step);
      double t = bound.fraction;
      limited = bound.limited;
      const double slope = gradient.dot(step);
      // E sums thousands of terms, each exact to ~1e-16 of its size: below this predicted
      // decrease it cannot tell better from worse.
      const double noise = 1e-12 * (std::abs(energy) + 1e-300);
      if (predicted_floor && !(slope < -noise) && std::isfinite(slope) && std::abs(slope) < noise) {
        // At the precision floor: take the step if it lowers the residual.
        trial = x + t * step;
        const double e = problem.energy_gradient(trial, trial_gradient);
        if (std::isfinite(e) && residual_of(trial_gradient) < policy.floor_residual_factor * residual) {
          x.swap(trial);
          accepted = floor_step = true;
        } else if (shift > 0.0 && !unshifted_at_floor) {
          // A shifted step converges only linearly, and at the floor that can stall above the
          // tolerance; the energy is then within rounding of its minimum, where the shift's
          // safeguard is not needed: once more with the unshifted Hessian.
          unshifted_at_floor = true;
          shift = 0.0;
          continue;
        }
        break;
      }
      if (!(slope < 0.0)) {
        last_failure = "the Newton step was not a descent direction";
        if (exact && policy.project_psd) {
          if (!switch_to_projection()) return *stopped;
          continue;
        }
        if (!grow_shift()) return *stopped;
        continue;
      }
      int infinite_trials = 0;
      for (int k = 0; k < policy.max_line_search_steps; ++k) {
        trial = x + t * step;
        ++summary.energy_evaluations;
        const double e = problem.energy(trial);
        if (std::isnan(e)) ++nan_trials;
        if (std::isfinite(e) && e <= energy + policy.armijo * t * slope) {
          accepted = true;
          break;
        }
        if (!std::isfinite(e)) {
          ++infinite_trials;
        } else if (predicted_floor && -t * slope < noise) {
          // The decrease drowns in round-off: accept a step that lowers the residual (the
          // quantity the stopping test measures) instead.
          problem.energy_gradient(trial, trial_gradient);
          accepted = residual_of(trial_gradient) < policy.floor_residual_factor * residual;
          break;
        } else if (!predicted_floor && k == 0 && std::abs(e - energy) <= 1e-12 * std::abs(energy)) {
          // The full step changes E by less than its rounding: take it if it cuts the residual.
          problem.energy_gradient(trial, trial_gradient);
          if (trial_gradient.allFinite() && residual_of(trial_gradient) <= policy.floor_residual_factor * residual) {
            accepted = true;
            break;
          }
        }
        t *= 0.5;
        limited = true;
      }
      if (accepted) {
        x.swap(trial);
        break;
      }
      last_failure = "no Armijo step in " + std::to_string(policy.max_line_search_steps) + " halvings (" +
                     std::to_string(infinite_trials) + " trial points had non-finite energy)";
      if (exact && policy.project_psd && policy.project_after_failed_line_search) {
        if (!switch_to_projection()) return *stopped;
        continue;
      }
      if (!predicted_floor && -slope <= 1e-12 * std::abs(energy))
        return finish(NewtonStatus::line_search_failed,
                      "the energy cannot decrease further within rounding (residual " + format_number(residual) +
                          " > tolerance " + format_number(options.tolerance) +
                          "): the tolerance is below what this problem can resolve");
      if (!grow_shift()) return *stopped;
    }
    if (!accepted) {
      // At the precision limit the residual may sit just above the tolerance.
      if (residual <= policy.roundoff_converged_factor * options.tolerance)
        return finish(NewtonStatus::converged, "stopped at the round-off floor of the energy");
      return finish(NewtonStatus::line_search_failed, "no step decreased the energy (residual " +
                                                          format_number(residual) + ", tolerance " +
                                                          format_number(options.tolerance) + ")");
    }

    ++summary.iterations;
    if (shift > 0.0) ++summary.regularised_steps;
    if (!exact) ++summary.projected_steps;
    if (exact || skip_exact) exact_failed_last = false;
    if (!floor_step) {
      if (limited && policy.limited_step_growth > 1.0) {
        shift = std::min(shift * policy.limited_step_growth, policy.shift_max);
      } else {
        shift = std::max(shift * policy.shift_shrink, policy.shift_floor);
        if (policy.shift_floor == 0.0 && shift < policy.shift_start) shift = 0.0;
      }
    }
    problem.prepare(x);
    energy = problem.energy_gradient(x, gradient);
    if (!std::isfinite(energy))
      return finish(NewtonStatus::non_finite, "the energy became non-finite after the problem was prepared for the new state");
    residual = gradient.allFinite() ? residual_of(gradient) : std::numeric_limits<double>::quiet_NaN();
    if (watch_readout) {
      problem.readout(x, next_readout);
      summary.readout_change = infinity_norm(next_readout - readout);
      quiet_steps = summary.readout_change <= 0.25 * options.readout_tolerance ? quiet_steps + 1 : 0;
      last_step_full = !limited && !floor_step;
      readout.swap(next_readout);
    }
  }
}

}  // namespace yarnfit::numerics
