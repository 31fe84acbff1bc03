#include "yarn_fit/homogenise/rest_shape.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <Eigen/LU>

namespace yarnfit::yarn {

int reset_rest_shape(YarnSystem& system, const Eigen::VectorXd& g, double max_length_change, double omega) {
  YarnTile& tile = system.mutable_tile();
  int clamped = 0;
  for (std::size_t e = 0; e < tile.edges.size(); ++e) {
    auto& edge = tile.edges[e];
    const double length = (system.position(g, edge.v1, edge.cell1) - system.position(g, edge.v0, {0, 0})).norm();
    const double input = tile.input_rest_lengths[e];
    const double lo = (1.0 - max_length_change) * input;
    const double hi = (1.0 + max_length_change) * input;
    const double target = edge.rest_length + omega * (length - edge.rest_length);
    edge.rest_length = std::clamp(target, lo, hi);
    if (target <= lo || target >= hi) ++clamped;
  }
  for (auto& c : tile.corners) {
    const double k = corner_curvature(system.position(g, c.v_prev, c.cell_prev),
                                        system.position(g, c.vertex, {0, 0}),
                                        system.position(g, c.v_next, c.cell_next));
    c.rest_curvature = std::max(0.0, c.rest_curvature + omega * (k - c.rest_curvature));
  }
  return clamped;
}

namespace {

// Symmetric in-plane strain E from its coordinates (E00, E11, E01) and back.
Eigen::Matrix2d strain_of(const Eigen::Vector3d& e) {
  Eigen::Matrix2d m;
  m << e[0], e[2], e[2], e[1];
  return m;
}
Eigen::Vector3d stress_coordinates(const Eigen::Matrix2d& p) {
  return {p(0, 0), p(1, 1), 0.5 * (p(0, 1) + p(1, 0))};
}

// Solves P(E) = 0 for the period stretch E by chord Newton with a finite-difference ∂P/∂E
// taken once at E = 0. Each evaluation re-equilibrates the tile at χ = 0 from the current g.
void relax_period(YarnSystem& system, Eigen::VectorXd& g, const RestShapeOptions& options,
                  RestShapeResult& out) {
  const YarnTile base = system.tile();
  const auto evaluate = [&](const Eigen::Vector3d& e, Eigen::VectorXd& state, EquilibriumResult& solve) {
    system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + strain_of(e)));
    system.set_deformation(CoarseDeformation{});
    solve = solve_equilibrium(system, state, options.solve);
    out.newton_iterations += solve.iterations;
    return stress_coordinates(system.coarse_stress(state));
  };
  const Eigen::Vector3d p0 = stress_coordinates(out.rest_stress);
  constexpr double h = 1e-3;
  Eigen::Matrix3d jacobian;
  for (int k = 0; k < 3; ++k) {
    Eigen::VectorXd state = g;
    EquilibriumResult solve;
    const Eigen::Vector3d pk = evaluate(h * Eigen::Vector3d::Unit(k), state, solve);
    if (!solve.converged) {
      system.set_tile(base);
      system.set_deformation(CoarseDeformation{});
      return;  // keep the heuristic's state; rest_stress reports what is left
    }
    jacobian.col(k) = (pk - p0) / h;
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(jacobian);
  if (!lu.isInvertible()) {
    system.set_tile(base);
    system.set_deformation(CoarseDeformation{});
    return;
  }
  Eigen::Vector3d e = Eigen::Vector3d::Zero(), p = p0;
  Eigen::VectorXd best_g = g;
  double best = p0.cwiseAbs().maxCoeff();
  Eigen::Vector3d best_e = e;
  EquilibriumResult best_solve = out.last_solve;
  for (int it = 0; it < options.period_iterations; ++it) {
    e = (e - lu.solve(p)).cwiseMax(-options.max_period_change).cwiseMin(options.max_period_change);
    Eigen::VectorXd state = best_g;
    EquilibriumResult solve;
    p = evaluate(e, state, solve);
    if (!solve.converged) break;
    if (p.cwiseAbs().maxCoeff() < best) {
      best = p.cwiseAbs().maxCoeff();
      best_e = e;
      best_g = state;
      best_solve = solve;
    }
  }
  system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + strain_of(best_e)));
  system.set_deformation(CoarseDeformation{});
  g = best_g;
  out.last_solve = best_solve;
  out.period_stretch = strain_of(best_e);
  out.rest_stress = system.coarse_stress(g);
}

}  // namespace

RestShapeResult relax_rest_shape(YarnSystem& system, Eigen::VectorXd& g, const RestShapeOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RestShapeResult out;
  system.set_deformation(CoarseDeformation{});
  if (g.size() != system.dof_count()) g = Eigen::VectorXd::Zero(system.dof_count());
  for (int round = 0; round < options.rounds; ++round) {
    EquilibriumOptions solve = options.solve;
    if (round < options.early_rounds) solve.max_iterations = options.early_iterations;
    out.last_solve = solve_equilibrium(system, g, solve);
    out.newton_iterations += out.last_solve.iterations;
    out.rounds = round + 1;
    out.clamped_edges = reset_rest_shape(system, g, options.max_length_change, options.over_relaxation);
  }
  // The last reset changed the rest shape: relax once more, to convergence, and measure.
  out.last_solve = solve_equilibrium(system, g, options.solve);
  out.newton_iterations += out.last_solve.iterations;
  out.converged = out.last_solve.converged;
  out.rest_stress = system.coarse_stress(g);
  out.stress_before_period = out.rest_stress;
  if (options.relax_period && out.converged) relax_period(system, g, options, out);
  const YarnTile& tile = system.tile();
  for (std::size_t e = 0; e < tile.edges.size(); ++e)
    out.max_length_change = std::max(out.max_length_change,
                                     std::abs(tile.edges[e].rest_length / tile.input_rest_lengths[e] - 1.0));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace yarnfit::yarn
