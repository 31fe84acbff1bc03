#include "yarn_fit/solver/equilibrium.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

namespace yarnfit::yarn {

const char* to_string(Termination t) {
  switch (t) {
    case Termination::converged: return "converged";
    case Termination::converged_loosely: return "converged_loosely";
    case Termination::max_iterations: return "max_iterations";
    case Termination::line_search_failed: return "line_search_failed";
    case Termination::non_finite: return "non_finite";
    case Termination::invalid_start: return "invalid_start";
    case Termination::time_limit: return "time_limit";
  }
  return "unknown";
}

namespace {
std::string format_force(double f) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g N", f);
  return buffer;
}
}  // namespace

namespace {
bool same_pattern(const Eigen::SparseMatrix<double>& m, const std::vector<int>& outer, const std::vector<int>& inner) {
  return m.isCompressed() && outer.size() == static_cast<std::size_t>(m.outerSize() + 1) &&
         inner.size() == static_cast<std::size_t>(m.nonZeros()) &&
         std::equal(outer.begin(), outer.end(), m.outerIndexPtr()) &&
         std::equal(inner.begin(), inner.end(), m.innerIndexPtr());
}
}  // namespace

Eigen::VectorXd projected_gradient(const YarnSystem& system, const Eigen::VectorXd& gradient) {
  const Eigen::MatrixXd& c = system.constraints();
  const Eigen::MatrixXd cct = c * c.transpose();
  const Eigen::VectorXd lambda = cct.ldlt().solve(c * gradient);
  return gradient - c.transpose() * lambda;
}

EquilibriumResult solve_equilibrium(YarnSystem& system, Eigen::VectorXd& g,
                                    const EquilibriumOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  EquilibriumResult result;
  const int n = system.dof_count();
  if (g.size() != n) g = Eigen::VectorXd::Zero(n);
  const Eigen::MatrixXd& c = system.constraints();
  // Project the start onto C g = 0 (a warm start from another tile state may drift).
  const Eigen::LDLT<Eigen::MatrixXd> cct_ldlt(c * c.transpose());
  g -= c.transpose() * cct_ldlt.solve(c * g);
  const double radius = system.tile().radius;
  const double step_cap = options.max_step_radii * radius;
  result.tolerance = options.force_tolerance > 0.0 ? options.force_tolerance : 1e-9 * system.params().ks2;

  const auto finish = [&](Termination reason, std::string message) {
    result.reason = reason;
    result.converged = reason == Termination::converged || reason == Termination::converged_loosely;
    result.message = std::move(message);
    result.constraint_violation = (c * g).lpNorm<Eigen::Infinity>();
    result.min_contact_distance = system.min_contact_distance(g);
    result.seconds = elapsed();
    return result;
  };

  // The Verlet list stays valid while every vertex moved less than skin/2 since its build;
  // a trial step adds up to step_cap, so rebuild before the margin runs out.
  const auto ensure_contacts = [&](const Eigen::VectorXd& at) {
    if (system.contacts_stale(at, step_cap)) {
      system.rebuild_contacts(at);
      ++result.contact_rebuilds;
    }
  };
  ensure_contacts(g);

  Eigen::VectorXd grad;
  double energy = system.energy_gradient(g, grad);
  if (!std::isfinite(energy) || !grad.allFinite()) {
    result.energy = energy;
    return finish(Termination::invalid_start,
                  "the start state has infinite or undefined energy (yarns overlap inside the "
                  "inner contact barrier)");
  }
  Eigen::VectorXd z = projected_gradient(system, grad);
  result.initial_residual = z.lpNorm<Eigen::Infinity>();
  result.residual = result.initial_residual;
  result.energy = energy;

  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;  // reads the lower triangle
  std::vector<int> analysed_outer, analysed_inner;                 // pattern of the last analysis
  YarnSystem::Triplets triplets;
  Eigen::SparseMatrix<double> k(n, n);
  constexpr double kShiftMin = 1e-10, kShiftMax = 1e2, kExactShiftMax = 1e-3;
  const bool use_exact = true;
  double shift_scale = 1e-8;  // α relative to the mean diagonal

  for (int it = 0; it < options.max_iterations; ++it) {
    result.iterations = it;
    if (result.residual <= result.tolerance) return finish(Termination::converged, "");
    if (it >= options.loose_after && result.residual <= options.loose_tolerance)
      return finish(Termination::converged_loosely,
                    "stopped after " + std::to_string(it) + " iterations within the loose tolerance (residual " +
                        format_force(result.residual) + ", loose tolerance " + format_force(options.loose_tolerance) + ")");
    if (options.time_limit_s > 0.0 && elapsed() > options.time_limit_s)
      return finish(Termination::time_limit, "time limit reached before convergence");

    // The exact Hessian gives quadratic convergence near equilibrium, where it is positive
    // definite on the constraint space; the per-element PSD projection is the safeguard when
    // it is not (far from equilibrium, or at an unstable state). Projected-only Newton
    // converges linearly when some elements are indefinite at the solution (edges in
    // compression, barrier curvature).
    bool projected = !use_exact;
    const auto assemble = [&] {
      triplets.clear();
      for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, 0.0);  // keeps the pattern fixed
      system.hessian(g, triplets, projected, /*lower_only=*/true);
      k.resize(n, n);
      k.setFromTriplets(triplets.begin(), triplets.end());
    };
    assemble();
    double mean_diag = std::max(k.diagonal().cwiseAbs().mean(), 1e-300);

    bool accepted = false;
    for (int attempt = 0; attempt < 8 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> kk = k;
      const double alpha = shift_scale * mean_diag;
      for (int i = 0; i < n; ++i) kk.coeffRef(i, i) += alpha;
      // The pattern follows the active contacts; the symbolic analysis (ordering and
      // elimination tree) is redone only when it changed.
      if (!same_pattern(kk, analysed_outer, analysed_inner)) {
        solver.analyzePattern(kk);
        analysed_outer.assign(kk.outerIndexPtr(), kk.outerIndexPtr() + kk.outerSize() + 1);
        analysed_inner.assign(kk.innerIndexPtr(), kk.innerIndexPtr() + kk.nonZeros());
      }
      solver.factorize(kk);
      const bool definite = solver.info() == Eigen::Success && solver.vectorD().minCoeff() > 0.0;
      // An indefinite exact Hessian is first shifted (Levenberg): the shifted step still
      // follows the directions of negative curvature out of a saddle, where the per-element
      // projection would discard them and creep (a bias-stretched stockinette otherwise
      // took hundreds of linearly converging iterations). A shift beyond 1e-3 of the mean
      // diagonal falls back to the projection, which takes longer steps far from equilibrium
      // (1e-3 was the best of 1e-7 … 1e-1 on cold and warm stockinette and rib solves).
      if (!definite && !projected && shift_scale < kExactShiftMax) {
        shift_scale = std::max(shift_scale * 10.0, 1e-6);
        --attempt;
        continue;
      }
      if (!definite && !projected) {
        projected = true;
        assemble();
        mean_diag = std::max(k.diagonal().cwiseAbs().mean(), 1e-300);
        --attempt;
        continue;
      }
      if (!definite) {
        shift_scale = std::min(shift_scale * 100.0, kShiftMax);
        continue;
      }
      const Eigen::VectorXd d0 = solver.solve(-grad);
      const Eigen::MatrixXd y = solver.solve(Eigen::MatrixXd(c.transpose()));
      const Eigen::MatrixXd s = c * y;
      const Eigen::VectorXd lambda = s.ldlt().solve(c * d0);
      Eigen::VectorXd delta = d0 - y * lambda;
      // g is kept exactly feasible, so the step must be too: remove the round-off part of
      // C δ, which would otherwise dominate the slope once the residual is tiny.
      delta -= c.transpose() * cct_ldlt.solve(c * delta);
      if (!delta.allFinite()) {
        shift_scale = std::min(shift_scale * 100.0, kShiftMax);
        continue;
      }
      // Step limits: displacement cap and collision-free fraction.
      double max_move = 0.0;
      for (int v = 0; v < n / 3; ++v) max_move = std::max(max_move, delta.segment<3>(3 * v).norm());
      double t = 1.0;
      bool limited = false;
      if (max_move > step_cap) {
        t = step_cap / max_move;
        limited = true;
      }
      const double t_safe = system.collision_free_fraction(g, t * delta);
      if (t_safe < 1.0) {
        t *= t_safe;
        limited = true;
      }
      const double slope = grad.dot(delta);
      // Energy round-off: below this predicted decrease, E cannot tell better from worse
      // (E sums thousands of terms, each exact to ~1e-16 of its size).
      const double noise = 1e-12 * (std::abs(energy) + 1e-300);
      if (!(slope < -noise) && std::isfinite(slope) && std::abs(slope) < noise) {
        // At the precision floor: take the step if it lowers the projected gradient.
        const Eigen::VectorXd trial = g + t * delta;
        Eigen::VectorXd trial_grad;
        const double e = system.energy_gradient(trial, trial_grad);
        if (std::isfinite(e) && projected_gradient(system, trial_grad).lpNorm<Eigen::Infinity>() < result.residual) {
          g = trial;
          accepted = true;
        }
        break;
      }
      if (!(slope < 0.0) && !projected) {
        projected = true;
        assemble();
        mean_diag = std::max(k.diagonal().cwiseAbs().mean(), 1e-300);
        --attempt;
        continue;
      }
      if (!(slope < 0.0)) {
        shift_scale = std::min(shift_scale * 100.0, kShiftMax);
        continue;
      }
      for (int ls = 0; ls < 40; ++ls) {
        const Eigen::VectorXd trial = g + t * delta;
        const double e = system.energy(trial);
        if (std::isfinite(e) && e <= energy + 1e-4 * t * slope) {
          g = trial;
          accepted = true;
          break;
        }
        if (std::isfinite(e) && -t * slope < noise) {
          // Near the solution the decrease drowns in round-off; accept a step that lowers
          // the projected gradient instead (the quantity the stopping test measures).
          Eigen::VectorXd trial_grad;
          system.energy_gradient(trial, trial_grad);
          if (projected_gradient(system, trial_grad).lpNorm<Eigen::Infinity>() < result.residual) {
            g = trial;
            accepted = true;
          }
          break;
        }
        t *= 0.5;
        limited = true;
      }
      if (accepted) {
        shift_scale = limited ? std::min(shift_scale * 4.0, kShiftMax) : std::max(shift_scale * 0.25, kShiftMin);
      } else {
        shift_scale = std::min(shift_scale * 100.0, kShiftMax);
      }
    }
    if (!accepted) {
      // At the precision limit the residual may sit just above the tolerance.
      if (result.residual <= 1e3 * result.tolerance)
        return finish(Termination::converged, "stopped at the round-off floor of the energy");
      return finish(Termination::line_search_failed,
                    "no step decreased the energy (residual " + format_force(result.residual) +
                        ", tolerance " + format_force(result.tolerance) + ")");
    }
    ensure_contacts(g);
    energy = system.energy_gradient(g, grad);
    if (!std::isfinite(energy) || !grad.allFinite())
      return finish(Termination::non_finite, "energy became non-finite after a contact rebuild");
    z = projected_gradient(system, grad);
    result.residual = z.lpNorm<Eigen::Infinity>();
    result.energy = energy;
  }
  result.iterations = options.max_iterations;
  if (result.residual <= result.tolerance) return finish(Termination::converged, "");

  return finish(Termination::max_iterations, "iteration limit reached (residual " +
                                                  format_force(result.residual) + ", tolerance " +
                                                  format_force(result.tolerance) + ")");
}

}  // namespace yarnfit::yarn
