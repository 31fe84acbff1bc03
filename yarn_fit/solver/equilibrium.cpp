#include "yarn_fit/solver/equilibrium.hpp"

#include <algorithm>
#include <cmath>

namespace yarnfit::yarn {
namespace {

// The yarn system as a Newton problem in g.
class EquilibriumProblem final : public numerics::NewtonProblem {
 public:
  EquilibriumProblem(YarnSystem& system, double step_cap) : m_system(system), m_step_cap(step_cap) {}

  [[nodiscard]] int size() const override { return m_system.dof_count(); }
  [[nodiscard]] double energy(const Eigen::VectorXd& g) const override { return m_system.energy(g); }
  double energy_gradient(const Eigen::VectorXd& g, Eigen::VectorXd& gradient) const override {
    return m_system.energy_gradient(g, gradient);
  }
  bool hessian(const Eigen::VectorXd& g, bool project_psd, numerics::Triplets& lower, std::string* /*why*/) const override {
    m_system.hessian(g, lower, project_psd, /*lower_only=*/true);
    return true;
  }
  [[nodiscard]] const Eigen::MatrixXd* constraints() const override { return &m_system.constraints(); }

  // The displacement cap first, then the collision-free fraction of the capped step.
  [[nodiscard]] StepBound max_step(const Eigen::VectorXd& g, const Eigen::VectorXd& dg) const override {
    double max_move = 0.0;
    for (Eigen::Index v = 0; v < dg.size() / 3; ++v) max_move = std::max(max_move, dg.segment<3>(3 * v).norm());
    StepBound bound;
    if (max_move > m_step_cap) {
      bound.fraction = m_step_cap / max_move;
      bound.limited = true;
    }
    const double safe = m_system.collision_free_fraction(g, bound.fraction * dg);
    if (safe < 1.0) {
      bound.fraction *= safe;
      bound.limited = true;
    }
    return bound;
  }

  // The Verlet list stays valid while every vertex moved less than skin/2 since its build;
  // a trial step adds up to the step cap, so rebuild before the margin runs out.
  void prepare(const Eigen::VectorXd& g) override {
    if (m_system.contacts_stale(g, m_step_cap)) {
      m_system.rebuild_contacts(g);
      ++m_rebuilds;
    }
  }
  // The coarse stress of an in-plane state (the bending read-out of a curved one is a
  // difference quotient of the map and is not watched).
  bool readout(const Eigen::VectorXd& g, Eigen::VectorXd& values) const override {
    if (m_system.deformation().curved()) return false;
    const Eigen::Matrix2d p = m_system.coarse_stress(g);
    values.resize(3);
    values << p(0, 0), p(1, 1), 0.5 * (p(0, 1) + p(1, 0));
    return true;
  }
  [[nodiscard]] std::string describe_invalid_energy(const Eigen::VectorXd& /*g*/) const override {
    return "yarns overlap inside the inner contact barrier";
  }
  [[nodiscard]] int rebuilds() const { return m_rebuilds; }

 private:
  YarnSystem& m_system;
  double m_step_cap;
  int m_rebuilds = 0;
};

}  // namespace

numerics::NewtonOptions equilibrium_newton_options(const YarnSystem& system, const EquilibriumOptions& options) {
  numerics::NewtonOptions o = numerics::NewtonOptions::for_yarn_tile();
  o.max_iterations = options.max_iterations;
  o.tolerance = options.force_tolerance > 0.0 ? options.force_tolerance : 1e-9 * system.params().ks2;
  o.time_limit_s = options.time_limit_s;
  o.loose_tolerance = options.loose_tolerance;
  o.loose_after = options.loose_after;
  o.readout_tolerance = options.stress_tolerance < 0.0 ? default_stress_tolerance(system) : options.stress_tolerance;
  return o;
}

double default_stress_tolerance(const YarnSystem& system) {
  return 1e-6 * system.params().ks1 / system.tile().shorter_period();
}

Eigen::VectorXd projected_gradient(const YarnSystem& system, const Eigen::VectorXd& gradient) {
  return numerics::projected_gradient(&system.constraints(), gradient);
}

EquilibriumResult solve_equilibrium(YarnSystem& system, Eigen::VectorXd& g, const EquilibriumOptions& options) {
  const double step_cap = options.max_step_radii * system.tile().radius;
  EquilibriumProblem problem(system, step_cap);
  EquilibriumResult result;
  static_cast<numerics::NewtonSummary&>(result) =
      numerics::solve_newton(problem, g, equilibrium_newton_options(system, options), &system.factorisation());
  result.contact_rebuilds = problem.rebuilds();
  result.constraint_violation = (system.constraints() * g).lpNorm<Eigen::Infinity>();
  result.min_contact_distance = system.min_contact_distance(g);
  return result;
}

}  // namespace yarnfit::yarn
