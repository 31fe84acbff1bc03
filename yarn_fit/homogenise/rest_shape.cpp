#include "yarn_fit/homogenise/rest_shape.hpp"

#include <algorithm>
#include <cmath>
#include <Eigen/LU>

#include "numerics/util/clock.hpp"

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
    const CornerFrames frames{tile.edges[static_cast<std::size_t>(c.edge_in)].anchor,
                              tile.edges[static_cast<std::size_t>(c.edge_out)].anchor};
    const Eigen::Vector2d k = corner_curvature(system.position(g, c.v_prev, c.cell_prev),
                                               system.position(g, c.vertex, {0, 0}),
                                               system.position(g, c.v_next, c.cell_next), frames);
    if (k.allFinite()) c.rest_curvature += omega * (k - c.rest_curvature);
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

// Solves P(E) = 0 for the period stretch E by chord Newton with a forward-difference ∂P/∂E
// taken once at E = 0. Each evaluation re-equilibrates the tile at χ = 0 from the current g.
// Unknowns: E00 and E11, and E01 only with `period_shear` (see RestShapeOptions).
void relax_period(YarnSystem& system, Eigen::VectorXd& g, const RestShapeOptions& options,
                  RestShapeResult& out) {
  const YarnTile base = system.tile();
  const int n = options.period_shear ? 3 : 2;
  const auto strain = [&](const Eigen::VectorXd& e) {
    Eigen::Vector3d full = Eigen::Vector3d::Zero();
    full.head(n) = e;
    return strain_of(full);
  };
  const auto evaluate = [&](const Eigen::VectorXd& e, Eigen::VectorXd& state, EquilibriumResult& solve) {
    system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + strain(e)));
    system.set_deformation(CoarseDeformation{});
    solve = solve_equilibrium(system, state, options.solve);
    out.newton_iterations += solve.iterations;
    return Eigen::VectorXd(stress_coordinates(system.coarse_stress(state)).head(n));
  };
  const auto restore_base = [&] {  // keep the rounds' state; rest_stress says what is left
    system.set_tile(base);
    system.set_deformation(CoarseDeformation{});
  };
  const Eigen::VectorXd p0 = stress_coordinates(out.rest_stress).head(n);
  constexpr double h = 1e-3;
  Eigen::MatrixXd jacobian(n, n);
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd state = g;
    EquilibriumResult solve;
    const Eigen::VectorXd pk = evaluate(h * Eigen::VectorXd::Unit(n, k), state, solve);
    if (!solve.converged()) return restore_base();
    jacobian.col(k) = (pk - p0) / h;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(jacobian);
  if (!lu.isInvertible()) return restore_base();
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n), p = p0;
  Eigen::VectorXd best_g = g, best_e = e;
  double best = p0.cwiseAbs().maxCoeff();
  EquilibriumResult best_solve = out.last_solve;
  for (int it = 0; it < options.period_iterations; ++it) {
    e = (e - lu.solve(p)).cwiseMax(-options.max_period_change).cwiseMin(options.max_period_change);
    Eigen::VectorXd state = best_g;
    EquilibriumResult solve;
    p = evaluate(e, state, solve);
    if (!solve.converged()) break;
    if (p.cwiseAbs().maxCoeff() < best) {
      best = p.cwiseAbs().maxCoeff();
      best_e = e;
      best_g = state;
      best_solve = solve;
    }
  }
  system.set_tile(transformed_tile(base, Eigen::Matrix2d::Identity() + strain(best_e)));
  system.set_deformation(CoarseDeformation{});
  g = best_g;
  out.last_solve = best_solve;
  out.period_stretch = strain(best_e);
  out.rest_stress = system.coarse_stress(g);
}

}  // namespace

RestShapeResult relax_rest_shape(YarnSystem& system, Eigen::VectorXd& g, const RestShapeOptions& given) {
  const auto start = numerics::Clock::now();
  // Every round solves to the force tolerance: the heuristic's fixed point depends on how far
  // each round relaxes, and rounds ended by the stress read-out test gave satin_small another
  // rest shape (σ_s at 10 % weft, c = −0.056: 45.8 N/m instead of 35.8).
  RestShapeOptions options = given;
  options.solve.stress_tolerance = 0.0;
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
  out.converged = out.last_solve.converged();
  out.rest_stress = system.coarse_stress(g);
  out.stress_before_period = out.rest_stress;
  if (options.relax_period && out.converged) relax_period(system, g, options, out);
  const YarnTile& tile = system.tile();
  for (std::size_t e = 0; e < tile.edges.size(); ++e)
    out.max_length_change = std::max(out.max_length_change,
                                     std::abs(tile.edges[e].rest_length / tile.input_rest_lengths[e] - 1.0));
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::yarn
