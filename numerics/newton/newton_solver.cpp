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
#include "numerics/util/error.hpp"
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

namespace {

// One call of solve_newton: the state carried from step to step, and the parts of a step, each
// a method called in the order solve() shows.
class NewtonRun {
 public:
  NewtonRun(NewtonProblem& problem, Eigen::VectorXd& x, const NewtonOptions& options, ShiftedLdlt& factor,
            Clock::time_point start)
      : m_problem(problem), m_x(x), m_options(options), m_policy(options.policy), m_factor(factor), m_start(start) {}

  NewtonSummary solve() {
    if (auto stop = begin()) return *stop;
    while (true) {
      if (auto stop = stop_test()) return *stop;
      if (auto stop = take_step()) return *stop;
      if (auto stop = after_step()) return *stop;
    }
  }

 private:
  NewtonSummary finish(NewtonStatus status, std::string message) {
    m_summary.status = status;
    m_summary.message = std::move(message);
    m_summary.analyses = m_factor.analyses() - m_analyses_before;
    m_summary.seconds = seconds_since(m_start);
    return m_summary;
  }

  // The residual the stopping test measures; with C the projected gradient of A.2.3.
  double residual_of(const Eigen::VectorXd& gradient) const {
    if (m_c == nullptr) return infinity_norm(gradient);
    return infinity_norm(gradient - m_c->transpose() * m_cct_ldlt.solve(*m_c * gradient));
  }

  // The start: projected onto C x = 0, its energy, gradient and residual.
  std::optional<NewtonSummary> begin() {
    m_summary.tolerance = m_options.tolerance;
    m_n = m_problem.size();
    if (m_x.size() != m_n) m_x = Eigen::VectorXd::Zero(m_n);
    m_c = m_problem.constraints();
    if (m_c != nullptr && m_c->rows() == 0) m_c = nullptr;
    if (m_c != nullptr) {
      // Project the start onto C x = 0 (a warm start from another state may drift).
      m_cct_ldlt.compute(*m_c * m_c->transpose());
      m_x -= m_c->transpose() * m_cct_ldlt.solve(*m_c * m_x);
    }
    m_analyses_before = m_factor.analyses();

    m_problem.prepare(m_x);
    m_energy = m_problem.energy_gradient(m_x, m_gradient);
    m_summary.energy = m_energy;
    if (!std::isfinite(m_energy)) {
      m_summary.residual = m_summary.initial_residual = std::numeric_limits<double>::quiet_NaN();
      const std::string what = m_problem.describe_invalid_energy(m_x);
      return finish(NewtonStatus::invalid_start,
                    "the start state's energy is not finite" + (what.empty() ? "" : ": " + what));
    }
    m_residual = m_gradient.allFinite() ? residual_of(m_gradient) : std::numeric_limits<double>::quiet_NaN();
    m_summary.initial_residual = m_residual;

    m_trial.resize(m_n);
    m_shift = m_policy.shift_initial;
    m_predicted_floor = m_policy.precision_floor == PrecisionFloor::predicted_decrease;
    m_watch_readout = m_options.readout_tolerance > 0.0 && m_problem.readout(m_x, m_readout);
    return std::nullopt;
  }

  // Before a step: the tests that end the solve at the current state.
  std::optional<NewtonSummary> stop_test() {
    if (!m_gradient.allFinite()) {
      const std::string what = m_problem.describe_invalid_gradient(m_x);
      return finish(NewtonStatus::non_finite,
                    "the gradient is not finite at a state of finite energy" + (what.empty() ? "" : " (from " + what + ")"));
    }
    m_summary.residual = m_residual;
    m_summary.energy = m_energy;
    const double residual = m_residual;
    const NewtonOptions& o = m_options;
    if (residual <= o.tolerance) return finish(NewtonStatus::converged, "");
    if (m_watch_readout && m_quiet_steps >= o.readout_steps && m_last_step_full)
      return finish(NewtonStatus::converged_readout,
                    "the read-out changed by at most " + format_number(o.readout_tolerance / 4.0) + " in each of the last " +
                        std::to_string(m_quiet_steps) + " steps (residual " + format_number(residual) + " > tolerance " +
                        format_number(o.tolerance) + ")");
    if (m_summary.iterations >= o.max_iterations)
      return finish(NewtonStatus::max_iterations, "stopped after " + std::to_string(m_summary.iterations) +
                                                      " iterations: residual " + format_number(residual) +
                                                      " > tolerance " + format_number(o.tolerance));
    if (m_summary.iterations >= o.loose_after && residual <= o.loose_tolerance)
      return finish(NewtonStatus::converged_loosely,
                    "stopped after " + std::to_string(m_summary.iterations) +
                        " iterations within the loose tolerance (residual " + format_number(residual) +
                        ", loose tolerance " + format_number(o.loose_tolerance) + ")");
    if (o.time_limit_s > 0.0 && seconds_since(m_start) > o.time_limit_s)
      return finish(NewtonStatus::time_limit, "time limit reached before convergence");
    return std::nullopt;
  }

  bool assemble() {
    m_triplets.clear();
    ++m_summary.assemblies;
    if (!m_problem.hessian(m_x, !m_exact, m_triplets, &m_why)) return false;
    m_factor.assemble(m_n, m_triplets);
    if (m_policy.shift_past_nonpositive_diagonal) {
      const double lowest = m_factor.relative_min_diagonal();
      if (lowest <= 0.0) m_shift = std::max(m_shift, m_policy.shift_start - lowest);
    }
    return true;
  }

  // After a failure: the projection replaces the exact Hessian (true), or the shift grows;
  // false when the solve must stop (m_stopped then holds the final summary).
  bool switch_to_projection() {
    m_exact = false;
    m_exact_failed_last = true;
    if (!assemble()) {
      m_stopped = finish(NewtonStatus::non_finite, m_why);
      return false;
    }
    return true;
  }

  bool grow_shift() {
    ++m_failed_attempts;
    m_shift = m_shift == 0.0 ? m_policy.shift_start : m_shift * m_policy.shift_growth;
    if (m_shift <= m_policy.shift_max) return true;
    if (!m_policy.fail_beyond_shift_max) {
      m_shift = m_policy.shift_max;
      return true;
    }
    std::string message = m_last_failure + " at every shift up to " + format_number(m_policy.shift_max) +
                          " x mean |diag H|; residual " + format_number(m_residual);
    if (m_nan_trials > 0)
      message += "; " + std::to_string(m_nan_trials) + " trial energies were NaN (a term breaks its contract)";
    m_stopped = finish(m_factorised_once ? NewtonStatus::line_search_failed : NewtonStatus::linear_solver_failed, message);
    return false;
  }

  // After a step that failed: the projection when the exact Hessian was used and may be
  // projected, else a larger shift.
  bool project_or_grow_shift() { return m_exact && m_policy.project_psd ? switch_to_projection() : grow_shift(); }

  // The state of a step, afresh.
  void reset_step() {
    m_accepted = false;
    m_floor_step = false;  // accepted at the precision floor without a line search
    m_unshifted_at_floor = false;
    m_limited = false;
    m_factorised_once = false;
    m_failed_attempts = 0;
    m_last_failure.clear();
    m_stopped.reset();
  }

  bool after_failed_step() {
    if (m_exact && m_policy.project_psd && m_policy.project_after_failed_line_search) return switch_to_projection();
    return grow_shift();
  }

  // The step from the factorised Hessian: Newton's, or with C the KKT step of (3.32) by the
  // Schur complement on the constraint rows (`kc`: K⁻¹Cᵀ when the inertia test computed it).
  Eigen::VectorXd newton_step(const Eigen::MatrixXd& kc) {
    const Eigen::VectorXd d0 = m_factor.solve(Eigen::VectorXd(-m_gradient));
    Eigen::VectorXd step = d0;
    if (m_c != nullptr) {
      const Eigen::MatrixXd y = kc.size() > 0 ? kc : m_factor.solve(Eigen::MatrixXd(m_c->transpose()));
      const Eigen::MatrixXd s = *m_c * y;
      const Eigen::VectorXd lambda = s.ldlt().solve(*m_c * d0);
      step = d0 - y * lambda;
      // x is kept exactly feasible, so the step must be too: remove the round-off part of
      // C δ, which would otherwise dominate the slope once the residual is tiny.
      step -= m_c->transpose() * m_cct_ldlt.solve(*m_c * step);
    }
    return step;
  }

  enum class FloorOutcome { accepted, retry_unshifted, none };

  // At the precision floor (the predicted decrease below the energy's rounding): take the step
  // if it lowers the residual.
  FloorOutcome step_at_floor(const Eigen::VectorXd& step, double t) {
    m_trial = m_x + t * step;
    const double e = m_problem.energy_gradient(m_trial, m_trial_gradient);
    if (std::isfinite(e) && residual_of(m_trial_gradient) < m_policy.floor_residual_factor * m_residual) {
      m_x.swap(m_trial);
      return FloorOutcome::accepted;
    }
    if (m_shift > 0.0 && !m_unshifted_at_floor) {
      // A shifted step converges only linearly, and at the floor that can stall above the
      // tolerance; the energy is then within rounding of its minimum, where the shift's
      // safeguard is not needed: once more with the unshifted Hessian.
      m_unshifted_at_floor = true;
      m_shift = 0.0;
      return FloorOutcome::retry_unshifted;
    }
    return FloorOutcome::none;
  }

  // Armijo's backtracking from the fraction `t` of the step; true when a trial point (in
  // m_trial) is accepted. Counts the trial points of non-finite energy.
  bool line_search(const Eigen::VectorXd& step, double t, double slope, double noise, int& infinite_trials) {
    for (int k = 0; k < m_policy.max_line_search_steps; ++k) {
      m_trial = m_x + t * step;
      ++m_summary.energy_evaluations;
      const double e = m_problem.energy(m_trial);
      if (std::isnan(e)) ++m_nan_trials;
      if (std::isfinite(e) && e <= m_energy + m_policy.armijo * t * slope) return true;
      if (!std::isfinite(e)) {
        ++infinite_trials;
      } else if (m_predicted_floor && -t * slope < noise) {
        // The decrease drowns in round-off: accept a step that lowers the residual (the
        // quantity the stopping test measures) instead.
        m_problem.energy_gradient(m_trial, m_trial_gradient);
        return residual_of(m_trial_gradient) < m_policy.floor_residual_factor * m_residual;
      } else if (!m_predicted_floor && k == 0 && std::abs(e - m_energy) <= 1e-12 * std::abs(m_energy)) {
        // The full step changes E by less than its rounding: take it if it cuts the residual.
        m_problem.energy_gradient(m_trial, m_trial_gradient);
        if (m_trial_gradient.allFinite() &&
            residual_of(m_trial_gradient) <= m_policy.floor_residual_factor * m_residual)
          return true;
      }
      t *= 0.5;
      m_limited = true;
    }
    return false;
  }

  // One accepted step (nothing returned), or the summary that ends the solve.
  std::optional<NewtonSummary> take_step() {
    // The exact Hessian first (the true Newton step, and no per-element eigen-decompositions)
    // unless the options or the last iteration say otherwise; the projection when it fails.
    m_skip_exact = m_policy.project_psd && m_policy.exact_hessian_first && m_policy.remember_projection &&
                   m_exact_failed_last;
    m_exact = !m_policy.project_psd || (m_policy.exact_hessian_first && !m_skip_exact);
    if (!assemble()) return finish(NewtonStatus::non_finite, m_why);

    reset_step();

    while (!m_accepted) {
      if (m_policy.max_failed_attempts > 0 && m_failed_attempts >= m_policy.max_failed_attempts) break;
      ++m_summary.factorisations;
      // K⁻¹Cᵀ, kept when the inertia test computed it for this factorisation.
      Eigen::MatrixXd kc;
      const bool definite = m_factor.factorise(m_shift) ||
                            (m_exact && m_c != nullptr && m_policy.accept_definite_on_constraints &&
                             positive_definite_on_constraints(m_factor, *m_c, &kc));
      if (!definite) {
        m_last_failure = "the shifted Hessian was not positive definite";
        if (m_exact && m_shift < m_policy.exact_shift_limit) {
          m_shift = std::max(m_shift * m_policy.exact_shift_growth, m_policy.exact_shift_floor);
          continue;
        }
        if (!project_or_grow_shift()) return m_stopped;
        continue;
      }
      m_factorised_once = true;
      const Eigen::VectorXd step = newton_step(kc);
      if (!step.allFinite()) {
        m_last_failure = "the Newton step was not finite";
        if (!after_failed_step()) return m_stopped;
        continue;
      }
      const NewtonProblem::StepBound bound = m_problem.max_step(m_x, step);
      const double t = bound.fraction;
      m_limited = bound.limited;
      const double slope = m_gradient.dot(step);
      // E sums thousands of terms, each exact to ~1e-16 of its size: below this predicted
      // decrease it cannot tell better from worse.
      const double noise = 1e-12 * (std::abs(m_energy) + 1e-300);
      if (m_predicted_floor && !(slope < -noise) && std::isfinite(slope) && std::abs(slope) < noise) {
        const FloorOutcome floor = step_at_floor(step, t);
        if (floor == FloorOutcome::retry_unshifted) continue;
        m_accepted = m_floor_step = floor == FloorOutcome::accepted;
        break;
      }
      if (!(slope < 0.0)) {
        m_last_failure = "the Newton step was not a descent direction";
        if (!project_or_grow_shift()) return m_stopped;
        continue;
      }
      int infinite_trials = 0;
      m_accepted = line_search(step, t, slope, noise, infinite_trials);
      if (m_accepted) {
        m_x.swap(m_trial);
        break;
      }
      m_last_failure = "no Armijo step in " + std::to_string(m_policy.max_line_search_steps) + " halvings (" +
                       std::to_string(infinite_trials) + " trial points had non-finite energy)";
      if (m_exact && m_policy.project_psd && m_policy.project_after_failed_line_search) {
        if (!switch_to_projection()) return m_stopped;
        continue;
      }
      if (!m_predicted_floor && -slope <= 1e-12 * std::abs(m_energy))
        return finish(NewtonStatus::line_search_failed,
                      "the energy cannot decrease further within rounding (residual " + format_number(m_residual) +
                          " > tolerance " + format_number(m_options.tolerance) +
                          "): the tolerance is below what this problem can resolve");
      if (!grow_shift()) return m_stopped;
    }
    if (!m_accepted) return no_step_found();
    return std::nullopt;
  }

  NewtonSummary no_step_found() {
    // At the precision limit the residual may sit just above the tolerance.
    if (m_residual <= m_policy.roundoff_converged_factor * m_options.tolerance)
      return finish(NewtonStatus::converged, "stopped at the round-off floor of the energy");
    return finish(NewtonStatus::line_search_failed, "no step decreased the energy (residual " +
                                                        format_number(m_residual) + ", tolerance " +
                                                        format_number(m_options.tolerance) + ")");
  }

  // After an accepted step: the counts, the shift for the next one, and the new state's energy,
  // residual and read-out.
  std::optional<NewtonSummary> after_step() {
    ++m_summary.iterations;
    if (m_shift > 0.0) ++m_summary.regularised_steps;
    if (!m_exact) ++m_summary.projected_steps;
    if (m_exact || m_skip_exact) m_exact_failed_last = false;
    if (!m_floor_step) {
      if (m_limited && m_policy.limited_step_growth > 1.0) {
        m_shift = std::min(m_shift * m_policy.limited_step_growth, m_policy.shift_max);
      } else {
        m_shift = std::max(m_shift * m_policy.shift_shrink, m_policy.shift_floor);
        if (m_policy.shift_floor == 0.0 && m_shift < m_policy.shift_start) m_shift = 0.0;
      }
    }
    m_problem.prepare(m_x);
    m_energy = m_problem.energy_gradient(m_x, m_gradient);
    if (!std::isfinite(m_energy))
      return finish(NewtonStatus::non_finite,
                    "the energy became non-finite after the problem was prepared for the new state");
    m_residual = m_gradient.allFinite() ? residual_of(m_gradient) : std::numeric_limits<double>::quiet_NaN();
    if (m_watch_readout) {
      m_problem.readout(m_x, m_next_readout);
      m_summary.readout_change = infinity_norm(m_next_readout - m_readout);
      m_quiet_steps = m_summary.readout_change <= 0.25 * m_options.readout_tolerance ? m_quiet_steps + 1 : 0;
      m_last_step_full = !m_limited && !m_floor_step;
      m_readout.swap(m_next_readout);
    }
    return std::nullopt;
  }

  NewtonProblem& m_problem;
  Eigen::VectorXd& m_x;
  const NewtonOptions& m_options;
  const NewtonPolicy& m_policy;
  ShiftedLdlt& m_factor;
  const Clock::time_point m_start;

  NewtonSummary m_summary;
  int m_n = 0;
  const Eigen::MatrixXd* m_c = nullptr;
  Eigen::LDLT<Eigen::MatrixXd> m_cct_ldlt;
  int m_analyses_before = 0;
  std::string m_why;
  Eigen::VectorXd m_gradient;
  double m_energy = 0.0;
  double m_residual = 0.0;
  Triplets m_triplets;
  Eigen::VectorXd m_trial, m_trial_gradient;
  double m_shift = 0.0;              // relative shift μ
  bool m_exact_failed_last = false;  // remember_projection: the exact Hessian failed last iteration
  int m_nan_trials = 0;              // trial energies that were NaN (a term breaking its contract)
  bool m_predicted_floor = false;
  // The read-out test: the read-out at x, and how many accepted steps in a row changed it by
  // at most a quarter of the tolerance.
  Eigen::VectorXd m_readout, m_next_readout;
  bool m_watch_readout = false;
  int m_quiet_steps = 0;
  bool m_last_step_full = false;

  // The step being taken.
  bool m_skip_exact = false;
  bool m_exact = false;
  bool m_accepted = false;
  bool m_floor_step = false;
  bool m_unshifted_at_floor = false;
  bool m_limited = false;
  bool m_factorised_once = false;
  int m_failed_attempts = 0;
  std::string m_last_failure;
  std::optional<NewtonSummary> m_stopped;
};

}  // namespace

NewtonSummary solve_newton(NewtonProblem& problem, Eigen::VectorXd& x, const NewtonOptions& options,
                           ShiftedLdlt* workspace) {
  const auto start = Clock::now();
  if (const Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "solve_newton: " + problems.one_line());
  ShiftedLdlt own_factor;
  NewtonRun run(problem, x, options, workspace != nullptr ? *workspace : own_factor, start);
  return run.solve();
}

}  // namespace yarnfit::numerics
