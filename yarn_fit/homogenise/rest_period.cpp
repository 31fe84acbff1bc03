#include "yarn_fit/homogenise/rest_period.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "numerics/util/clock.hpp"

namespace yarnfit::yarn {
namespace {

// The strain diag(e) as a matrix.
Eigen::Matrix2d diagonal_strain(const Eigen::Vector2d& e) {
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  m.diagonal() = e;
  return m;
}

}  // namespace

RestPeriodResult relax_rest_period(YarnSystem& system, Eigen::VectorXd& g, const RestPeriodOptions& options) {
  const auto start = numerics::Clock::now();
  RestPeriodResult out;
  const YarnTile base = system.tile();
  if (g.size() != system.dof_count()) g = Eigen::VectorXd::Zero(system.dof_count());

  // P and the tile's energy W at period stretch e, equilibrated from `state` (updated);
  // false when the solve failed.
  double energy = 0.0;
  const auto stress_at = [&](const Eigen::Vector2d& e, Eigen::VectorXd& state, Eigen::Vector2d& p, double& w) {
    system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + diagonal_strain(e)));
    system.set_deformation(CoarseDeformation{});
    const EquilibriumResult solve = solve_equilibrium(system, state, options.solve);
    ++out.solves;
    out.newton_iterations += solve.iterations;
    if (!solve.converged()) {
      out.message = std::string("an equilibrium at rest did not converge (") + to_string(solve.status) + ": " +
                    solve.message + ")";
      return false;
    }
    const Eigen::Matrix2d full = system.coarse_stress(state);
    p = Eigen::Vector2d(full(0, 0), full(1, 1));
    w = solve.energy;
    return true;
  };
  // How far P is from done: the larger of |P_ii| / tolerance_i.
  const auto badness = [&](const Eigen::Vector2d& p) { return p.cwiseAbs().cwiseQuotient(options.tolerance).maxCoeff(); };

  Eigen::Vector2d e = Eigen::Vector2d::Zero(), p;
  Eigen::VectorXd state = g;
  const auto finish = [&] {
    system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + diagonal_strain(e)));
    system.set_deformation(CoarseDeformation{});
    out.period_stretch = diagonal_strain(e);
    out.rest_stress = system.coarse_stress(g);
    out.seconds = numerics::seconds_since(start);
    return out;
  };
  if (!stress_at(e, state, p, energy)) return finish();
  g = state;
  out.initial_stress = system.coarse_stress(g);
  for (; out.steps < options.max_steps; ++out.steps) {
    if (badness(p) <= 1.0) {
      out.converged = true;
      return finish();
    }
    // W(e) = min_g E: its gradient is A P_ii / (1 + e_i) (A the current tile's area, P the
    // stress against the current period), its Hessian about A ∂P/∂e, differenced.
    const double area = system.tile().area();
    const Eigen::Vector2d gradient = area * p.cwiseQuotient(Eigen::Vector2d::Ones() + e);
    Eigen::Matrix2d jacobian;
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd probe = g;
      Eigen::Vector2d pk;
      double wk = 0.0;
      if (!stress_at(e + options.jacobian_step * Eigen::Vector2d::Unit(k), probe, pk, wk)) return finish();
      jacobian.col(k) = area * (pk - p) / options.jacobian_step;
    }
    // Far from the rest period W need not be convex (loops buckle or contacts switch): shift
    // the symmetric Hessian until it is positive definite, so the step goes downhill.
    Eigen::Matrix2d hessian = 0.5 * (jacobian + jacobian.transpose());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(hessian);
    const double largest_curvature = eig.eigenvalues().cwiseAbs().maxCoeff();
    const double lowest = eig.eigenvalues().minCoeff();
    if (!(lowest > 1e-6 * largest_curvature)) hessian.diagonal().array() += 1e-3 * largest_curvature - lowest;
    Eigen::Vector2d step = -hessian.ldlt().solve(gradient);
    if (!step.allFinite() || !(largest_curvature > 0.0)) step = -gradient.cwiseSign() * options.max_step;
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > options.max_step) step *= options.max_step / largest;
    const double slope = gradient.dot(step);
    bool accepted = false;
    for (int h = 0; h <= options.halvings && !accepted; ++h, step *= 0.5) {
      Eigen::VectorXd trial = g;
      Eigen::Vector2d pt;
      double wt = 0.0;
      if (!stress_at(e + step, trial, pt, wt)) continue;
      // Armijo on W, or, where W no longer resolves the change, a smaller stress.
      if (wt <= energy + 1e-4 * std::ldexp(slope, -h) || (std::abs(wt - energy) <= 1e-12 * std::abs(energy) &&
                                                           badness(pt) < badness(p))) {
        e += step;
        p = pt;
        g = trial;
        energy = wt;
        accepted = true;
      }
    }
    if (!accepted) {
      out.message = "no period step lowered the tile's energy (max |P_ii| / tolerance " + std::to_string(badness(p)) + ")";
      return finish();
    }
    out.message.clear();
  }
  out.converged = badness(p) <= 1.0;
  if (!out.converged)
    out.message = "rest stress still " + std::to_string(badness(p)) + " tolerances after " +
                  std::to_string(options.max_steps) + " period steps";
  return finish();
}

}  // namespace yarnfit::yarn
