#include "yarn_fit/homogenise/rest_shape.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

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
  const YarnTile& tile = system.tile();
  for (std::size_t e = 0; e < tile.edges.size(); ++e)
    out.max_length_change = std::max(out.max_length_change,
                                     std::abs(tile.edges[e].rest_length / tile.input_rest_lengths[e] - 1.0));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace yarnfit::yarn
