#pragma once
// Membrane (in-plane) energy of the thin shell on linear triangles (thesis 6.3.1, SPEC §3):
//
//   E(x) = Σ_t A_t Ψ(F_t),   F_t = D_s D_m⁻¹                                       [J]
//
// with A_t the rest area, D_m = [X1 − X0, X2 − X0] the rest edge matrix (2×2, lab frame),
// D_s = [x1 − x0, x2 − x0] the deformed one (dim×2) and Ψ the law (6.1) of InplaneMaterial.
// dim = 2: planar scene (clamped stretch), F is 2×2 and J = det F is signed, so the log term
// of Ψ is a barrier against inversion. dim = 3: a surface in 3-D (pear loop), F is 3×2,
// C = FᵀF and J = √det C.
//
// Derivatives per element, with F = Σ_i x_i b_iᵀ (b_i the rows of B = [−1ᵀD_m⁻¹; D_m⁻¹]):
//   ∂E/∂x_i = A P b_i,   ∂²E/∂x_i∂x_j = A (b_i ⊗ I)ᵀ ∂P/∂F (b_j ⊗ I)
// assembled as 6×6 (dim 2) or 9×9 (dim 3) blocks, optionally projected to PSD per element.
//
// The parameter sensitivities of the energy and of its gradient are the same term evaluated
// with the law ∂Ψ/∂p_k (InplaneMaterial::parameter_derivative: for the parameters Ψ is linear
// in, a unit parameter k and the others zero), used for implicit-function sensitivities in
// the fit. p = the fourteen of k_inplane_param_names (eq. 6.1's six, the lock-up pairs, the shares).

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "numerics/terms/energy_term.hpp"
#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/energies/inplane_material.hpp"

namespace yarnfit::shell {

class MembraneTerm final : public numerics::EnergyTerm {
 public:
  static constexpr int parameter_count = k_inplane_param_count;  // k_inplane_param_names

  // Copies what it needs from `mesh` (no reference is kept). Throws an input Error when
  // dim is not 2 or 3 or a triangle has non-positive rest area (not counter-clockwise).
  MembraneTerm(const ShellMesh& mesh, const InplaneParams& params, int dim);

  [[nodiscard]] std::string name() const override { return "membrane"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override;
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void add_hessian(const Eigen::VectorXd& x, numerics::Triplets& h, const numerics::HessianOptions& options) const override;

  using ParameterVector = Eigen::Matrix<double, parameter_count, 1>;
  // Adds ∂(∇E)/∂p_k into column k of `G` (#dofs × parameter_count).
  void add_gradient_per_parameter(const Eigen::VectorXd& x, Eigen::MatrixXd& G) const;
  // ∂E/∂p_k; for the parameters E is linear in (all but the lock-up rates and shares) this is E with unit
  // parameter k and the others zero, so E = Σ_{k linear} p_k · entry k wherever E is finite.
  [[nodiscard]] ParameterVector value_per_parameter(const Eigen::VectorXd& x) const;

  // Changes the stiffnesses without rebuilding the rest geometry (the fit does this often).
  void set_params(const InplaneParams& params);
  [[nodiscard]] const InplaneMaterial& material() const { return m_material; }
  [[nodiscard]] int dim() const { return m_dim; }
  [[nodiscard]] int dof_count() const { return m_dim * m_vertex_count; }

  // Per-element rest data, exposed for tests and stress output.
  struct Element {
    std::array<int, 3> v{0, 0, 0};
    double area = 0.0;              // rest area A_t [m²]
    Eigen::Matrix<double, 3, 2> b;  // rows b_i: F = Σ_i x_i b_iᵀ
  };
  [[nodiscard]] const std::vector<Element>& elements() const { return m_elements; }

 private:
  int m_dim = 2;
  int m_vertex_count = 0;
  std::vector<Element> m_elements;
  InplaneMaterial m_material;
  // The laws ∂Ψ/∂p_k at the current parameters, for the per-parameter derivatives.
  std::vector<InplaneMaterial> m_unit_materials;
};

}  // namespace yarnfit::shell
