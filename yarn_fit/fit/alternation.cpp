#include "yarn_fit/fit/alternation.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::yarn {

namespace {

using numerics::Clock;
using numerics::k_inf;

// dθ/du of each coordinate at x (ParameterSpace: log-space coordinates are exponential in u).
Eigen::VectorXd unit_derivative(const swarm::ParameterSpace& space, const Eigen::VectorXd& x) {
  Eigen::VectorXd out(space.dimension());
  for (int i = 0; i < space.dimension(); ++i) {
    const swarm::Parameter& p = space.parameter(i);
    out[i] = p.log_space ? x[i] * std::log(p.upper / p.lower) : p.upper - p.lower;
  }
  return out;
}

// The residuals of one round on its held rest state, for Ceres, in the unit cube. Every
// evaluation computes r and its exact Jacobian together (the sensitivities cost about one
// Newton iteration per sample) and keeps them for the call that asks for the Jacobian at the
// same point (Ceres evaluates a trial point first and linearises it after accepting it). Each
// evaluation starts its samples where the best one so far left them.
class HeldRestResiduals final : public ceres::CostFunction {
 public:
  HeldRestResiduals(const YarnObjective& objective, const RestState& rest, const swarm::ParameterSpace& space,
                    const PointToParams& to_params, const std::vector<yarn::YarnParam>& wanted, int residuals,
                    const std::function<void(double)>& after_evaluation)
      : m_objective(objective), m_rest(rest), m_space(space), m_to_params(to_params), m_wanted(wanted),
        m_after(after_evaluation) {
    set_num_residuals(residuals);
    mutable_parameter_block_sizes()->push_back(space.dimension());
  }

  // The model Ceres minimises: the held residuals plus the secant estimate of what relaxing
  // the rest state would add, B (u − origin) (Alternation::update_secant).
  void set_secant(const Eigen::MatrixXd& b, const Eigen::VectorXd& origin) {
    m_secant = b;
    m_origin = origin;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::VectorXd> u(parameters[0], m_space.dimension());
    if (!(m_have && u == m_u)) evaluate(u);
    if (!m_ok) return false;  // Ceres rejects the step and shrinks its region
    Eigen::Map<Eigen::VectorXd> r(residuals, num_residuals());
    r = m_r;
    if (m_secant.size() > 0) r += m_secant * (u - m_origin);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> j(
          jacobians[0], num_residuals(), m_space.dimension());
      j = m_j_unit;
      if (m_secant.size() > 0) j += m_secant;
    }
    return true;
  }

  // Takes an evaluation at u made elsewhere (the round's accepted point, on this rest state
  // from its own samples) as the cached one and as the best so far.
  void seed(const Eigen::VectorXd& u, const ObjectiveResult& result) {
    m_u = u;
    m_have = true;
    take(result, m_space.from_unit(u));
  }
  // The last evaluation.
  [[nodiscard]] bool ok() const { return m_ok; }
  [[nodiscard]] const ObjectiveResult& last() const { return m_last; }
  [[nodiscard]] const Eigen::VectorXd& residuals() const { return m_r; }
  [[nodiscard]] Eigen::MatrixXd jacobian_log() const {
    return residual_jacobian(m_last) * m_to_params_log_scale.asDiagonal();
  }
  [[nodiscard]] int evaluations() const { return m_evaluations; }
  [[nodiscard]] int failures() const { return m_failures; }
  [[nodiscard]] double best() const { return m_best; }

 private:
  void evaluate(const Eigen::VectorXd& u) const {
    m_have = true;
    m_u = u;
    const Eigen::VectorXd x = m_space.from_unit(u);
    const yarn::YarnParams params = m_to_params(x);
    AtRestOptions options;
    options.wanted = m_wanted;
    options.record_states = true;
    options.warm = m_best_states.empty() ? nullptr : &m_best_states;
    take(m_objective.evaluate_at_rest(m_rest, params, options), x);
    ++m_evaluations;
    if (!m_ok) ++m_failures;
    if (m_after) m_after(m_best);
  }

  void take(const ObjectiveResult& result, const Eigen::VectorXd& x) const {
    const yarn::YarnParams params = m_to_params(x);
    m_last = result;
    m_ok = m_last.ok;
    if (m_ok) {
      m_r = residual_vector(m_last);
      m_ok = m_r.size() == num_residuals() && m_r.allFinite();
    }
    if (m_ok) {
      const Eigen::MatrixXd j = residual_jacobian(m_last);
      m_j_unit = j * unit_derivative(m_space, x).asDiagonal();
      m_to_params_log_scale.resize(static_cast<Eigen::Index>(m_wanted.size()));
      for (std::size_t k = 0; k < m_wanted.size(); ++k)
        m_to_params_log_scale[static_cast<Eigen::Index>(k)] = yarn::get(params, m_wanted[k]);
      m_ok = m_j_unit.allFinite();
    }
    if (m_ok && m_last.value < m_best) {
      m_best = m_last.value;
      m_best_states.clear();
      for (const auto& d : m_last.directions) m_best_states.push_back(d.states);
    }
    if (m_ok) {  // the model's best: where Ceres ends
      const double model = (m_secant.size() > 0 ? Eigen::VectorXd(m_r + m_secant * (m_u - m_origin)) : m_r).squaredNorm();
      if (model < m_best_model) {
        m_best_model = model;
        m_best_model_u = m_u;
        m_best_model_r = m_r;
      }
    }
  }

 public:
  // The held residuals (without the secant term) where the model was lowest.
  [[nodiscard]] const Eigen::VectorXd& best_model_point() const { return m_best_model_u; }
  [[nodiscard]] const Eigen::VectorXd& best_model_residuals() const { return m_best_model_r; }

 private:

  const YarnObjective& m_objective;
  const RestState& m_rest;
  const swarm::ParameterSpace& m_space;
  const PointToParams& m_to_params;
  const std::vector<yarn::YarnParam>& m_wanted;
  std::function<void(double)> m_after;
  mutable bool m_have = false, m_ok = false;
  mutable Eigen::VectorXd m_u, m_r, m_to_params_log_scale;
  mutable Eigen::MatrixXd m_j_unit;
  mutable ObjectiveResult m_last;
  mutable std::vector<SweepStates> m_best_states;
  mutable double m_best = k_inf;
  Eigen::MatrixXd m_secant;
  Eigen::VectorXd m_origin;
  mutable double m_best_model = k_inf;
  mutable Eigen::VectorXd m_best_model_u, m_best_model_r;
  mutable int m_evaluations = 0, m_failures = 0;
};

ceres::Solver::Options held_run_options(const AlternationSettings& settings) {
  ceres::Solver::Options o;
  o.minimizer_type = ceres::TRUST_REGION;
  o.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = settings.iterations_per_round;
  // A zero-residual recovery goes from g ~ 1e-2 to 1e-6 and below: stop on a negligible
  // relative decrease or step, not on the gradient's size.
  o.function_tolerance = 1e-6;
  o.parameter_tolerance = 1e-6;
  o.gradient_tolerance = 1e-14;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  // A round whose start cannot be evaluated (an equilibrium not reached) is the fit's to handle:
  // it falls back to implicit filtering and its summary says why. Ceres would also log that as an
  // error on the user's terminal ("Terminating: Residual and Jacobian evaluation failed"), in
  // the middle of the progress display.
  FLAGS_minloglevel = std::max(FLAGS_minloglevel, 3);
  return o;
}

// The alternation's current point: its rest state, relaxed there from the tile as read, and its
// evaluation on it from the rest state's own samples (= YarnObjective::evaluate, with the
// Jacobian).
struct Accepted {
  Eigen::VectorXd u;  // unit cube
  RestState rest;
  ObjectiveResult result;
  [[nodiscard]] double g() const { return result.value; }
};

class Alternation {
 public:
  Alternation(const YarnObjective& objective, const swarm::ParameterSpace& space, const PointToParams& to_params,
              const AlternationSettings& settings, const AlternationProgress& progress, AlternationSummary& out)
      : m_objective(objective), m_space(space), m_to_params(to_params), m_settings(settings), m_progress(progress),
        m_out(out), m_residuals(2 * objective.options().samples * static_cast<int>(objective.scales().size())) {
    for (const auto& p : space.parameters()) {
      const auto param = yarn::yarn_param_from_string(p.name);
      if (!param) throw Error(ErrorCategory::input, "alternation: '" + p.name + "' is not a yarn parameter");
      m_wanted.push_back(*param);
    }
  }

  // The point u with its own rest state, or nothing (the reason in the summary's message).
  std::optional<Accepted> relax_and_evaluate(const Eigen::VectorXd& u) {
    Accepted a;
    a.u = u;
    a.rest = m_objective.rest_state(params_at(u));
    if (!a.rest.ok) {
      m_out.message = a.rest.message;
      return std::nullopt;
    }
    AtRestOptions options;
    options.wanted = m_wanted;
    options.record_states = true;
    a.result = m_objective.evaluate_at_rest(a.rest, params_at(u), options);
    count(a.result.ok, a.result.ok ? a.result.value : k_inf);
    if (!a.result.ok) {
      m_out.message = a.result.message;
      return std::nullopt;
    }
    return a;
  }

  // Gauss–Newton on a's held rest state, inside the box |u − a.u|∞ ≤ radius.
  struct HeldRun {
    Eigen::VectorXd u;
    double g = k_inf;  // of the model (the held rest state and the secant term)
    Eigen::VectorXd held_residuals;  // at u, on the held rest state alone (empty if unknown)
    bool failed = false;
    int iterations = 0, evaluations = 0;
    std::string termination;
  };
  HeldRun held_run(const Accepted& a, double radius) {
    auto* cost = new HeldRestResiduals(m_objective, a.rest, m_space, m_to_params, m_wanted, m_residuals,
                                       [&](double best) { count(true, best); });
    cost->set_secant(m_secant, a.u);
    cost->seed(a.u, a.result);
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    Eigen::VectorXd block = a.u;
    problem.AddResidualBlock(cost, nullptr, block.data());
    for (int i = 0; i < m_space.dimension(); ++i) {
      problem.SetParameterLowerBound(block.data(), i, std::max(0.0, a.u[i] - radius));
      problem.SetParameterUpperBound(block.data(), i, std::min(1.0, a.u[i] + radius));
    }
    ceres::Solver::Summary summary;
    ceres::Solve(held_run_options(m_settings), &problem, &summary);
    HeldRun h;
    h.u = block.cwiseMax(0.0).cwiseMin(1.0);
    h.g = 2.0 * summary.final_cost;
    if (cost->best_model_point().size() == h.u.size() && (cost->best_model_point() - h.u).cwiseAbs().maxCoeff() < 1e-12)
      h.held_residuals = cost->best_model_residuals();
    h.iterations = static_cast<int>(summary.iterations.size()) - 1;
    h.evaluations = cost->evaluations();
    m_out.failed_evaluations += cost->failures();
    h.termination = ceres::TerminationTypeToString(summary.termination_type);
    if (!summary.message.empty()) h.termination += ": " + summary.message;
    h.failed = summary.termination_type == ceres::FAILURE || !summary.IsSolutionUsable();
    if (h.failed) h.u = a.u;
    return h;
  }

  [[nodiscard]] yarn::YarnParams params_at(const Eigen::VectorXd& u) const { return m_to_params(m_space.from_unit(u)); }

  // After a held run from `from` ended at `trial`, whose own rest state gave `at_trial`: a
  // Broyden update of B, the secant estimate of what relaxing the rest state adds to the
  // residuals, r(θ) ≈ r_held(θ) + B (u − u_k). Holding the rest state leaves that dependence
  // out of the Jacobian; the secant learns it along the directions the rounds move in, so
  // that the rounds converge like a quasi-Newton method instead of at the rate at which the
  // rest shape follows the parameters.
  void update_secant(const Accepted& from, const HeldRun& run, const Accepted& at_trial) {
    if (run.held_residuals.size() == 0) return;
    const Eigen::VectorXd step = run.u - from.u;
    const double length2 = step.squaredNorm();
    if (!(length2 > 0.0)) return;
    if (m_secant.size() == 0) m_secant = Eigen::MatrixXd::Zero(run.held_residuals.size(), step.size());
    const Eigen::VectorXd predicted = run.held_residuals + m_secant * step;
    const Eigen::VectorXd actual = residual_vector(at_trial.result);
    if (actual.size() != predicted.size()) return;
    m_secant += (actual - predicted) * step.transpose() / length2;
  }
  [[nodiscard]] const Eigen::MatrixXd& secant() const { return m_secant; }
  void forget_secant() { m_secant.resize(0, 0); }

  // Measures what relaxing the rest state adds to the residuals' derivative at a, by forward
  // differences of the point's own residuals (each a fresh relaxation) less the held Jacobian,
  // and makes it the model's B. With it, r_held(u) + B (u − a.u) is r(u) to first order in every
  // direction. One relaxation and evaluation per coordinate; false (B unchanged) when one fails.
  bool measure_rest_derivative(const Accepted& a, double step) {
    const Eigen::VectorXd r0 = residual_vector(a.result);
    const Eigen::MatrixXd held = residual_jacobian(a.result) * unit_derivative(m_space, m_space.from_unit(a.u)).asDiagonal();
    if (held.rows() != r0.size() || held.cols() != a.u.size()) return false;
    Eigen::MatrixXd b(r0.size(), a.u.size());
    for (int i = 0; i < a.u.size(); ++i) {
      Eigen::VectorXd u = a.u;
      const double h = u[i] + step <= 1.0 ? step : -step;  // stay inside the box
      u[i] += h;
      const RestState rest = m_objective.rest_state(params_at(u));
      if (!rest.ok) {
        count(false, k_inf);
        return false;
      }
      // Without sensitivities, unlike a's own evaluation. Evaluating these with them too was
      // tried: it moved the measured B and changed which valley a knit fit ended in
      // (docs/calibration.md, "Woven tiles").
      const ObjectiveResult r = m_objective.evaluate_at_rest(rest, params_at(u), AtRestOptions{});
      count(r.ok, r.ok ? r.value : k_inf);
      if (!r.ok) return false;
      const Eigen::VectorXd ri = residual_vector(r);
      if (ri.size() != r0.size() || !ri.allFinite()) return false;
      b.col(i) = (ri - r0) / h - held.col(i);
    }
    m_secant = b;
    return true;
  }

 private:
  void count(bool ok, double best) {
    ++m_out.evaluations;
    if (!ok) ++m_out.failed_evaluations;
    m_best_seen = std::min(m_best_seen, best);
    if (m_progress) m_progress(m_out.evaluations, m_best_seen);
  }

  const YarnObjective& m_objective;
  const swarm::ParameterSpace& m_space;
  const PointToParams& m_to_params;
  const AlternationSettings& m_settings;
  const AlternationProgress& m_progress;
  AlternationSummary& m_out;
  int m_residuals;
  std::vector<yarn::YarnParam> m_wanted;
  double m_best_seen = k_inf;
  Eigen::MatrixXd m_secant;  // m × d, unit cube; empty until a round has compared
};

// The profile's linearisation at an accepted point: r and dr/d log θ.
void keep_linearisation(const Accepted& a, const std::vector<double>& theta, AlternationSummary& out) {
  out.residuals = residual_vector(a.result);
  Eigen::VectorXd scale(static_cast<Eigen::Index>(theta.size()));
  for (std::size_t k = 0; k < theta.size(); ++k) scale[static_cast<Eigen::Index>(k)] = theta[k];
  out.jacobian_log = residual_jacobian(a.result) * scale.asDiagonal();
}

// Rounds of the alternation from `at` (updated to the last accepted point): Gauss–Newton on the
// held rest state inside a box of half-width `radius` around the point, then the trial point's
// own rest state and g; accepted when g fell, the box growing after a step the held model
// predicted well and shrinking after one it did not (a trust region on the alternation: the
// held rest state is a good model of g only near the point it was relaxed at).
void run_rounds(Alternation& alternation, const AlternationSettings& settings, Accepted& at, AlternationSummary& out) {
  double radius = settings.initial_radius;
  int failures_in_a_row = 0;  // towards the fallback
  int failed_in_a_row = 0;     // every failed round, for the message
  Eigen::VectorXd measured_at;  // where the rest state's derivative was last measured
  const auto measured_here = [&] { return measured_at.size() > 0 && measured_at == at.u; };
  for (int k = 1; k <= settings.max_rounds; ++k) {
    const auto round_start = Clock::now();
    AlternationRound round;
    round.round = k;
    round.g_start = at.g();
    const auto held = alternation.held_run(at, radius);
    round.g_end = held.g;
    round.iterations = held.iterations;
    round.evaluations = held.evaluations + 1;
    round.termination = held.termination;
    round.move = (held.u - at.u).cwiseAbs().maxCoeff();
    out.last_move = round.move;
    if (!held.failed && round.move < settings.move_tolerance) {  // the point is the alternation's fixed point
      out.converged = true;
      round.accepted = true;
      round.g_true = at.g();
    } else if (!held.failed) {
      std::optional<Accepted> trial = alternation.relax_and_evaluate(held.u);
      if (trial && round.move <= settings.secant_move) alternation.update_secant(at, held, *trial);
      round.g_true = trial ? trial->g() : k_inf;
      round.accepted = trial && trial->g() < at.g();
      bool mispredicted = !round.accepted;
      if (round.accepted) {
        const double ratio = (at.g() - trial->g()) / std::max(at.g() - held.g, 1e-300);
        if (ratio > 0.75 && round.move > 0.9 * radius) radius = std::min(2.0 * radius, 0.5);
        else if (ratio < 0.25) radius *= 0.5;
        mispredicted = ratio < 0.25;
        at = std::move(*trial);
      } else {
        radius = 0.5 * round.move;
        // It led the model astray. (Even a derivative measured at this point is dropped: keeping
        // it was tried, docs/calibration.md, "Woven tiles".)
        alternation.forget_secant();
      }
      // A model that mispredicted lacked the rest state's response: measure it where the next
      // round starts, once per point.
      if (mispredicted && settings.rest_difference_step > 0.0 && !measured_here()) {
        const int before = out.evaluations;
        round.rest_derivative_measured = alternation.measure_rest_derivative(at, settings.rest_difference_step);
        round.evaluations += out.evaluations - before;
        if (round.rest_derivative_measured) {
          measured_at = at.u;
        } else {
          round.termination += "; the rest state's derivative could not be measured (a relaxation failed)";
        }
      }
    }
    round.failed = held.failed || !round.accepted;
    round.seconds = numerics::seconds_since(round_start);
    out.rounds.push_back(round);
    // A rejected round that measured the rest state's derivative has given the next round a
    // better model, not a reason to give up.
    failed_in_a_row = round.failed ? failed_in_a_row + 1 : 0;
    if (!round.failed) failures_in_a_row = 0;
    else if (!round.rest_derivative_measured) ++failures_in_a_row;
    if (out.converged) return;
    if (failures_in_a_row >= settings.failures_before_fallback) {
      out.fallback_reason = std::to_string(failed_in_a_row) + " rounds in a row found no lower g (last: " +
                            (held.failed ? held.termination : "g " + std::to_string(round.g_true) + " at the trial") + ")";
      return;
    }
    if (radius < settings.move_tolerance) {
      out.converged = true;  // the held model and g agree on no step longer than the tolerance
      return;
    }
  }
}

void fall_back(const YarnObjective& objective, const swarm::ParameterSpace& space, const PointToParams& to_params,
               const AlternationSettings& settings, const AlternationProgress& progress, AlternationSummary& out) {
  out.fell_back = true;
  const swarm::ResidualObjective residuals = [&](const Eigen::VectorXd& x) {
    const ObjectiveResult r = objective.evaluate(to_params(x));
    if (!r.ok) throw Error(ErrorCategory::solve, r.message);
    return residual_vector(r);
  };
  const int before = out.evaluations;
  out.fallback = swarm::run_implicit_filtering(space, residuals, out.best_point, settings.fallback,
                                               [&](const swarm::ImplicitFilteringSummary& p) {
                                                 if (progress) progress(before + p.evaluations, p.best_value);
                                               });
  out.evaluations += out.fallback.evaluations;
  out.failed_evaluations += out.fallback.failed;
  if (out.fallback.usable() && out.fallback.best_value < out.best_value) {
    out.best_value = out.fallback.best_value;
    out.best_point = out.fallback.best_point;
    out.residuals.resize(0);
    out.jacobian_log.resize(0, 0);
  }
}

}  // namespace

db::Problems AlternationSettings::problems() const {
  db::Problems out;
  if (max_rounds < 1) out.add_field("max_rounds", "must be at least 1 (got " + std::to_string(max_rounds) + ")");
  if (iterations_per_round < 1)
    out.add_field("iterations_per_round", "must be at least 1 (got " + std::to_string(iterations_per_round) + ")");
  if (!(initial_radius > 0.0 && initial_radius <= 1.0)) out.add_field("initial_radius", "must be in (0, 1]");
  if (!(move_tolerance > 0.0 && move_tolerance < 1.0)) out.add_field("move_tolerance", "must be in (0, 1)");
  if (failures_before_fallback < 1) out.add_field("failures_before_fallback", "must be at least 1");
  if (!(rest_difference_step >= 0.0 && rest_difference_step < 0.5))
    out.add_field("rest_difference_step", "must be in [0, 0.5) (0: never measure the rest state's derivative)");
  out.append(fallback.problems(), "fallback.");
  return out;
}

std::string AlternationSummary::brief_report() const {
  std::ostringstream out;
  out << "alternation " << (converged ? "converged" : "stopped") << " after " << rounds.size() << " round"
      << (rounds.size() == 1 ? "" : "s") << " (last move " << last_move << " of the ranges), " << evaluations
      << " evaluations";
  if (failed_evaluations > 0) out << " (" << failed_evaluations << " failed)";
  out << ", g " << start_value << " -> " << best_value << ", " << seconds << " s";
  if (fell_back) out << "; fell back to implicit filtering: " << fallback_reason;
  return out.str();
}

AlternationSummary run_alternation(const YarnObjective& objective, const swarm::ParameterSpace& space,
                                   const PointToParams& to_params, const Eigen::VectorXd& start,
                                   const AlternationSettings& settings, const AlternationProgress& progress) {
  if (const db::Problems problems = settings.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "alternation settings: " + problems.one_line());
  if (const auto outside = space.bounds_problems(start); !outside.empty())
    throw Error(ErrorCategory::input, "alternation start: " + outside.front());
  const auto t0 = Clock::now();
  AlternationSummary out;
  out.best_value = out.start_value = k_inf;
  Alternation alternation(objective, space, to_params, settings, progress, out);
  std::optional<Accepted> at = alternation.relax_and_evaluate(space.to_unit(start));
  if (at) {
    out.start_value = at->g();
    run_rounds(alternation, settings, *at, out);
    out.best_point = space.from_unit(at->u);
    out.best_value = at->g();
    std::vector<double> theta;
    for (const double v : out.best_point) theta.push_back(v);
    keep_linearisation(*at, theta, out);
  }
  if (!out.fallback_reason.empty() && out.best_point.size() > 0) fall_back(objective, space, to_params, settings, progress, out);
  out.ok = out.best_point.size() > 0 && std::isfinite(out.best_value);
  if (!out.ok && out.message.empty()) out.message = "no round evaluated its start";
  out.seconds = numerics::seconds_since(t0);
  return out;
}

}  // namespace yarnfit::yarn
