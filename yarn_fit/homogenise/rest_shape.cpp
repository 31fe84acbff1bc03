#include "yarn_fit/homogenise/rest_shape.hpp"

#include <algorithm>
#include <cmath>

#include "numerics/roots/chord_newton.hpp"

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

// The coarse rest stress P(E) at χ = 0 as a function of the period stretch E's coordinates
// (E00, E11, and E01 only with `period_shear`), for numerics' chord Newton: every evaluation
// re-equilibrates the tile from the best state so far.
class RestStressOfPeriod final : public numerics::ChordNewtonProblem {
 public:
  RestStressOfPeriod(YarnSystem& system, const Eigen::VectorXd& g, const RestShapeOptions& options, RestShapeResult& out)
      : m_system(system), m_base(system.tile()), m_n(options.period_shear ? 3 : 2), m_options(options), m_out(out),
        m_best_g(g), m_best_solve(out.last_solve) {}

  bool evaluate(const Eigen::VectorXd& e, Eigen::VectorXd& p) override {
    m_system.set_tile(transformed_tile(m_base, Eigen::Matrix2d::Identity() + strain(e)));
    m_system.set_deformation(CoarseDeformation{});
    m_state = m_best_g;
    m_solve = solve_equilibrium(m_system, m_state, m_options.solve);
    m_out.newton_iterations += m_solve.iterations;
    p = stress_coordinates(m_system.coarse_stress(m_state)).head(m_n);
    return m_solve.converged();
  }
  void keep() override {
    m_best_g = m_state;
    m_best_solve = m_solve;
  }

  [[nodiscard]] int size() const { return m_n; }
  [[nodiscard]] const YarnTile& base() const { return m_base; }
  [[nodiscard]] Eigen::Matrix2d strain(const Eigen::VectorXd& e) const {
    Eigen::Vector3d full = Eigen::Vector3d::Zero();
    full.head(m_n) = e;
    return strain_of(full);
  }
  [[nodiscard]] const Eigen::VectorXd& best_g() const { return m_best_g; }
  [[nodiscard]] const EquilibriumResult& best_solve() const { return m_best_solve; }

 private:
  YarnSystem& m_system;
  const YarnTile m_base;
  const int m_n;
  const RestShapeOptions& m_options;
  RestShapeResult& m_out;
  Eigen::VectorXd m_best_g, m_state;
  EquilibriumResult m_best_solve, m_solve;
};

// The rest-shape heuristic's period chord steps (RestShapeOptions::period_chord_steps): P(E)
// = 0 by chord Newton with a forward-difference ∂P/∂E taken once at E = 0, the best of its
// steps kept. When ∂P/∂E cannot be had, the tile keeps the rounds' period.
void period_chord_steps(YarnSystem& system, Eigen::VectorXd& g, const RestShapeOptions& options,
                        RestShapeResult& out) {
  RestStressOfPeriod stress(system, g, options, out);
  numerics::ChordNewtonOptions chord;
  chord.steps = options.period_chord_steps;
  chord.max_abs = options.max_period_change;
  chord.jacobian_step = 1e-3;
  const int n = stress.size();
  const numerics::ChordNewtonResult r =
      numerics::chord_newton(stress, Eigen::VectorXd::Zero(n), stress_coordinates(out.rest_stress).head(n), chord);
  if (r.status == numerics::ChordNewtonStatus::jacobian_failed) {
    // Keep the rounds' state; rest_stress says what is left.
    system.set_tile(stress.base());
    system.set_deformation(CoarseDeformation{});
    return;
  }
  system.set_tile(transformed_tile(stress.base(), Eigen::Matrix2d::Identity() + stress.strain(r.x)));
  system.set_deformation(CoarseDeformation{});
  g = stress.best_g();
  out.last_solve = stress.best_solve();
  out.period_stretch = stress.strain(r.x);
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
  if (options.period_chord_steps > 0 && out.converged) period_chord_steps(system, g, options, out);
  const YarnTile& tile = system.tile();
  for (std::size_t e = 0; e < tile.edges.size(); ++e)
    out.max_length_change = std::max(out.max_length_change,
                                     std::abs(tile.edges[e].rest_length / tile.input_rest_lengths[e] - 1.0));
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::yarn
