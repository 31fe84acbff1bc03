#include "swarm/implicit_filtering.hpp"

#include <omp.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::swarm {

namespace {

using numerics::Clock;
using numerics::k_inf;

// One evaluation: the unit point, its residuals and g = |r|², or why it failed.
struct Point {
  Eigen::VectorXd u;
  Eigen::VectorXd r;
  double value = k_inf;
  Evaluation outcome;
};

// r at the unit point u; a residual vector of another length than `expected` (when ≥ 0) or
// with non-finite entries is a failure. Never throws: it runs inside an OpenMP region.
Point evaluate_at(const ParameterSpace& space, const ResidualObjective& f, const Eigen::VectorXd& u,
                  Eigen::Index expected) noexcept {
  Point p;
  p.u = u;
  p.outcome = evaluate_guarded([&] {
    Eigen::VectorXd r = f(space.from_unit(u));
    if (r.size() == 0) throw Error(ErrorCategory::solve, "the residual vector is empty");
    if (expected >= 0 && r.size() != expected)
      throw Error(ErrorCategory::solve, "the residual vector has " + std::to_string(r.size()) +
                                            " entries, the start's had " + std::to_string(expected));
    if (!r.allFinite()) throw Error(ErrorCategory::solve, "a residual is not finite");
    p.r = std::move(r);
    return p.r.squaredNorm();
  });
  if (p.outcome.ok) p.value = p.outcome.value;
  return p;
}

}  // namespace

numerics::Problems ImplicitFilteringSettings::problems() const {
  numerics::Problems out;
  add_local_stopping_problems(out, max_evaluations, max_seconds, stop_value, max_failures_kept);
  if (!(initial_scale > 0.0 && initial_scale <= 0.5))
    out.add_field("initial_scale", "must be in (0, 0.5] (fraction of the range)");
  if (!(min_scale > 0.0 && min_scale <= initial_scale)) out.add_field("min_scale", "must be in (0, initial_scale]");
  if (!(shrink > 0.0 && shrink < 1.0)) out.add_field("shrink", "must be in (0, 1)");
  if (!(max_step_scales >= 1.0) || std::isinf(max_step_scales)) out.add_field("max_step_scales", "must be finite and ≥ 1");
  if (line_search_steps < 0) out.add_field("line_search_steps", "must be ≥ 0");
  if (!(levenberg >= 0.0) || std::isinf(levenberg)) out.add_field("levenberg", "must be finite and ≥ 0");
  if (threads < 0) out.add_field("threads", "must be ≥ 0 (0: OpenMP's default)");
  return out;
}

const char* to_string(ImplicitFilteringStatus status) {
  switch (status) {
    case ImplicitFilteringStatus::converged: return "converged: stencil scale below min_scale";
    case ImplicitFilteringStatus::stop_value: return "reached stop_value";
    case ImplicitFilteringStatus::max_evaluations: return "evaluation limit reached";
    case ImplicitFilteringStatus::max_time: return "time limit reached";
    case ImplicitFilteringStatus::start_failed: return "the start could not be evaluated";
  }
  return "unknown";
}

const char* to_string(ImplicitFilteringMove move) {
  switch (move) {
    case ImplicitFilteringMove::gauss_newton: return "gauss_newton";
    case ImplicitFilteringMove::stencil_point: return "stencil_point";
    case ImplicitFilteringMove::shrink: return "shrink";
  }
  return "unknown";
}

bool ImplicitFilteringSummary::usable() const { return std::isfinite(best_value); }

std::string ImplicitFilteringSummary::brief_report() const {
  std::ostringstream s;
  s << "implicit filtering " << message << ": " << evaluations << " evaluations (" << failed << " failed), "
    << history.size() << " iterations, ";
  if (usable()) {
    s << "best " << best_value << " from " << start_value << ", scale " << final_scale;
  } else {
    s << "no successful evaluation";
  }
  s << ", " << seconds << " s";
  return s.str();
}

ImplicitFilteringSummary run_implicit_filtering(const ParameterSpace& space, const ResidualObjective& residuals,
                                                const Eigen::VectorXd& start,
                                                const ImplicitFilteringSettings& settings,
                                                const ImplicitFilteringProgress& progress) {
  if (const numerics::Problems problems = settings.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "implicit filtering settings: " + problems.one_line());
  Eigen::VectorXd u;
  try {
    u = space.to_unit(start);
  } catch (const Error& e) {
    throw with_context("implicit filtering start: ", e);
  }
  const auto t0 = Clock::now();
  const auto elapsed = [&] { return numerics::seconds_since(t0); };
  const auto out_of_time = [&] { return settings.max_seconds > 0.0 && elapsed() >= settings.max_seconds; };
  const int threads = settings.threads > 0 ? settings.threads : omp_get_max_threads();

  ImplicitFilteringSummary s;
  s.best_point = start;
  s.final_scale = settings.initial_scale;
  const auto record = [&](const Point& p) {
    const int index = s.evaluations++;
    if (p.outcome.ok) return;
    ++s.failed;
    keep_failure(s.failures, settings.max_failures_kept, index, 0, -1, space.from_unit(p.u), p.outcome.message);
  };
  const auto finish = [&](ImplicitFilteringStatus status, const std::string& detail = {}) {
    s.status = status;
    s.message = std::string(to_string(status)) + detail;
    s.seconds = elapsed();
    return s;
  };

  Point centre = evaluate_at(space, residuals, u, -1);
  record(centre);
  s.start_value = centre.value;
  if (!centre.outcome.ok) return finish(ImplicitFilteringStatus::start_failed, ": " + centre.outcome.message);
  s.best_value = centre.value;
  if (progress) progress(s);
  const Eigen::Index m = centre.r.size();
  const int d = space.dimension();
  double h = settings.initial_scale;

  while (true) {
    s.final_scale = h;
    if (centre.value <= settings.stop_value) return finish(ImplicitFilteringStatus::stop_value);
    if (h < settings.min_scale) return finish(ImplicitFilteringStatus::converged);
    if (out_of_time()) return finish(ImplicitFilteringStatus::max_time);

    // The stencil: u ± h eᵢ inside the box (a side that would leave it is left out).
    std::vector<Eigen::VectorXd> points;
    std::vector<int> coordinate;
    for (int i = 0; i < d; ++i) {
      for (const double sign : {-1.0, 1.0}) {
        Eigen::VectorXd v = u;
        v[i] = std::clamp(u[i] + sign * h, 0.0, 1.0);
        if (v[i] == u[i]) continue;
        points.push_back(std::move(v));
        coordinate.push_back(i);
      }
    }
    const int n_points = static_cast<int>(points.size());
    if (s.evaluations + n_points > settings.max_evaluations)
      return finish(ImplicitFilteringStatus::max_evaluations, " (the next stencil needs " + std::to_string(n_points) + ")");
    std::vector<Point> stencil(static_cast<std::size_t>(n_points));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int k = 0; k < n_points; ++k)
      stencil[static_cast<std::size_t>(k)] = evaluate_at(space, residuals, points[static_cast<std::size_t>(k)], m);
    for (const Point& p : stencil) record(p);

    // J by central differences where both sides are in, one-sided where one is.
    Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(m, d);
    for (int i = 0; i < d; ++i) {
      const Point* lo = nullptr;
      const Point* hi = nullptr;
      for (int k = 0; k < n_points; ++k) {
        const Point& p = stencil[static_cast<std::size_t>(k)];
        if (coordinate[static_cast<std::size_t>(k)] != i || !p.outcome.ok) continue;
        (p.u[i] < u[i] ? lo : hi) = &p;
      }
      if (lo && hi) jacobian.col(i) = (hi->r - lo->r) / (hi->u[i] - lo->u[i]);
      else if (hi) jacobian.col(i) = (hi->r - centre.r) / (hi->u[i] - u[i]);
      else if (lo) jacobian.col(i) = (centre.r - lo->r) / (u[i] - lo->u[i]);
    }
    int best_k = -1;
    double best_stencil = centre.value;
    for (int k = 0; k < n_points; ++k) {
      const Point& p = stencil[static_cast<std::size_t>(k)];
      if (p.outcome.ok && p.value < best_stencil) {
        best_stencil = p.value;
        best_k = k;
      }
    }

    ImplicitFilteringIteration it;
    it.scale = h;
    // Gauss–Newton step with a small Levenberg term (a column of zeros, a parameter the
    // residuals do not see at this scale, gets no step), limited to the stencil's reach.
    const Eigen::MatrixXd jtj = jacobian.transpose() * jacobian;
    Eigen::MatrixXd damped = jtj;
    for (int i = 0; i < d; ++i) damped(i, i) = jtj(i, i) > 0.0 ? jtj(i, i) * (1.0 + settings.levenberg) : 1.0;
    Eigen::VectorXd step = damped.ldlt().solve(-jacobian.transpose() * centre.r);
    if (!step.allFinite()) step.setZero();
    const double largest = step.cwiseAbs().maxCoeff();
    const double reach = settings.max_step_scales * h;
    if (largest > reach) step *= reach / largest;
    bool moved = false;
    bool budget_spent = false;
    for (int t = 0; t < settings.line_search_steps; ++t) {
      const Eigen::VectorXd v = (u + step).cwiseMax(0.0).cwiseMin(1.0);
      if ((v - u).cwiseAbs().maxCoeff() == 0.0) break;
      if (s.evaluations + 1 > settings.max_evaluations || out_of_time()) {
        budget_spent = true;
        break;
      }
      Point trial = evaluate_at(space, residuals, v, m);
      record(trial);
      ++it.trials;
      if (trial.outcome.ok && trial.value < best_stencil) {
        centre = std::move(trial);
        it.move = ImplicitFilteringMove::gauss_newton;
        moved = true;
        break;
      }
      step *= 0.5;
    }
    if (!moved && best_k >= 0) {
      centre = std::move(stencil[static_cast<std::size_t>(best_k)]);
      it.move = ImplicitFilteringMove::stencil_point;
      moved = true;
    }
    if (moved) {
      u = centre.u;
      s.best_value = centre.value;  // every move is to a point better than all seen
      s.best_point = space.from_unit(u);
    } else if (!budget_spent) {
      h *= settings.shrink;
      it.move = ImplicitFilteringMove::shrink;
    }
    it.evaluations = s.evaluations;
    it.value = centre.value;
    s.history.push_back(it);
    if (progress) progress(s);
    if (budget_spent && !moved) {
      s.final_scale = h;
      return finish(out_of_time() ? ImplicitFilteringStatus::max_time : ImplicitFilteringStatus::max_evaluations);
    }
  }
}

}  // namespace yarnfit::swarm
