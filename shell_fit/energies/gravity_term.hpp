#pragma once
// Gravity on the shell in 3-D scenes (pear loop; SPEC §3 "Shell"), with lumped masses:
//
//   m_v = ρ Σ_{t ∋ v} A_t / 3,   E(x) = Σ_v m_v g z_v                                  [J]
//
// ρ the areal density [kg/m²], A_t the rest triangle areas, z = coordinate 2 (up). Linear in
// x: the gradient is constant and the Hessian is empty.

#include <Eigen/Core>
#include <string>

#include "numerics/terms/energy_term.hpp"
#include "shell_fit/core/shell_mesh.hpp"

namespace yarnfit::shell {

class GravityTerm final : public numerics::EnergyTerm {
 public:
  static constexpr int dim = 3;

  // Throws an input Error for a negative or non-finite density or g.
  GravityTerm(const ShellMesh& mesh, double areal_density, double g = 9.81);

  [[nodiscard]] std::string name() const override { return "gravity"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override;
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void add_hessian(const Eigen::VectorXd& x, numerics::Triplets& h, const numerics::HessianOptions& options) const override;

  // Lumped vertex masses [kg], #V.
  [[nodiscard]] const Eigen::VectorXd& masses() const { return m_masses; }
  [[nodiscard]] double total_mass() const { return m_masses.sum(); }
  [[nodiscard]] double gravity() const { return m_g; }

 private:
  Eigen::VectorXd m_masses;
  double m_g = 9.81;
};

}  // namespace yarnfit::shell
