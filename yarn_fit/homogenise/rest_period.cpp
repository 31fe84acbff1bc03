#include "yarn_fit/homogenise/rest_period.hpp"

#include <string>

#include "numerics/newton/few_dof_newton.hpp"

#include "numerics/util/clock.hpp"

namespace yarnfit::yarn {
namespace {

// The strain diag(e) as a matrix.
Eigen::Matrix2d diagonal_strain(const Eigen::Vector2d& e) {
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  m.diagonal() = e;
  return m;
}

// The tile's energy W as a function of its period stretches e = (E00, E11), for the few-dof
// Newton of numerics: each value is an equilibrium at χ = 0 warm-started from the last
// accepted state. W's gradient is A P_ii / (1 + e_i) (A the current tile's area, P the
// stress against the current period), its Hessian about A ∂P/∂e, differenced.
class PeriodEnergy final : public numerics::FewDofProblem<2> {
 public:
  PeriodEnergy(YarnSystem& system, Eigen::VectorXd& g, const RestPeriodOptions& options, RestPeriodResult& out)
      : m_system(system), m_base(system.tile()), m_g(g), m_options(options), m_out(out) {}

  bool evaluate(const Eigen::Vector2d& e, numerics::FewDofPoint<2>& at) override {
    m_trial = m_g;
    Eigen::Vector2d p;
    if (!stress_at(e, m_trial, p, at.value)) return false;
    at.gradient = m_system.tile().area() * p.cwiseQuotient(Eigen::Vector2d::Ones() + e);
    at.residual = badness(p);
    m_trial_stress = p;
    return true;
  }
  void accept() override {
    m_g.swap(m_trial);
    m_stress = m_trial_stress;
    if (m_first) m_out.initial_stress = m_system.coarse_stress(m_g);
    m_first = false;
  }
  bool hessian(const Eigen::Vector2d& e, const numerics::FewDofPoint<2>& /*at*/, Eigen::Matrix2d& h) override {
    const double area = m_system.tile().area();
    for (int k = 0; k < 2; ++k) {
      Eigen::VectorXd probe = m_g;
      Eigen::Vector2d pk;
      double wk = 0.0;
      if (!stress_at(e + m_options.jacobian_step * Eigen::Vector2d::Unit(k), probe, pk, wk)) return false;
      h.col(k) = area * (pk - m_stress) / m_options.jacobian_step;
    }
    return true;
  }
  // How far P is from done: the larger of |P_ii| / tolerance_i.
  [[nodiscard]] double badness(const Eigen::Vector2d& p) const {
    return p.cwiseAbs().cwiseQuotient(m_options.tolerance).maxCoeff();
  }
  [[nodiscard]] const YarnTile& base() const { return m_base; }

 private:
  // P and the tile's energy W at period stretch e, equilibrated from `state` (updated);
  // false when the solve failed (its message in the result).
  bool stress_at(const Eigen::Vector2d& e, Eigen::VectorXd& state, Eigen::Vector2d& p, double& w) {
    m_system.set_tile(transformed_tile(m_base, Eigen::Matrix2d::Identity() + diagonal_strain(e)));
    m_system.set_deformation(CoarseDeformation{});
    const EquilibriumResult solve = solve_equilibrium(m_system, state, m_options.solve);
    ++m_out.solves;
    m_out.newton_iterations += solve.iterations;
    if (!solve.converged()) {
      m_out.message = std::string("an equilibrium at rest did not converge (") + to_string(solve.status) + ": " +
                      solve.message + ")";
      return false;
    }
    const Eigen::Matrix2d full = m_system.coarse_stress(state);
    p = Eigen::Vector2d(full(0, 0), full(1, 1));
    w = solve.energy;
    return true;
  }

  YarnSystem& m_system;
  const YarnTile m_base;
  Eigen::VectorXd& m_g;  // the accepted state
  const RestPeriodOptions& m_options;
  RestPeriodResult& m_out;
  Eigen::VectorXd m_trial;  // the state of the last evaluation
  Eigen::Vector2d m_stress = Eigen::Vector2d::Zero(), m_trial_stress = Eigen::Vector2d::Zero();  // P accepted, P tried
  bool m_first = true;
};

}  // namespace

RestPeriodResult relax_rest_period(YarnSystem& system, Eigen::VectorXd& g, const RestPeriodOptions& options) {
  const auto start = numerics::Clock::now();
  RestPeriodResult out;
  if (g.size() != system.dof_count()) g = Eigen::VectorXd::Zero(system.dof_count());
  PeriodEnergy energy(system, g, options, out);
  numerics::FewDofNewtonOptions newton;
  newton.max_steps = options.max_steps;
  newton.max_step = options.max_step;
  newton.halvings = options.halvings;
  Eigen::Vector2d e = Eigen::Vector2d::Zero();
  const numerics::FewDofNewtonResult<2> r = numerics::minimise_few_dofs(energy, e, newton);
  out.steps = r.steps;
  out.converged = r.status == numerics::FewDofNewtonStatus::converged;
  switch (r.status) {
    case numerics::FewDofNewtonStatus::converged: out.message.clear(); break;
    case numerics::FewDofNewtonStatus::evaluation_failed: break;  // the solve's message
    case numerics::FewDofNewtonStatus::no_descent:
      out.message = "no period step lowered the tile's energy (max |P_ii| / tolerance " + std::to_string(r.at.residual) + ")";
      break;
    case numerics::FewDofNewtonStatus::max_steps:
      out.message = "rest stress still " + std::to_string(r.at.residual) + " tolerances after " +
                    std::to_string(options.max_steps) + " period steps";
      break;
  }
  system.set_tile(transformed_tile(energy.base(), Eigen::Matrix2d::Identity() + diagonal_strain(e)));
  system.set_deformation(CoarseDeformation{});
  out.period_stretch = diagonal_strain(e);
  out.rest_stress = system.coarse_stress(g);
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::yarn
