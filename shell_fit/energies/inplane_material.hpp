#pragma once
// In-plane constitutive law of the thin shell: anisotropic StVK augmented with a Neo-Hookean
// area term (thesis 6.3.1, eq. 6.1; SPEC §3 "Shell").
//
//   Ψ(F) = ½ εᵀ K ε + kn1 (J − 1)² + kn2 log² J                                  (6.1) [J/m²]
//   E   = ½ (FᵀF − I)                    Green strain in the lab frame
//   E_m = Rᵀ E R                         the same strain in the material frame, R = rot(φ)
//   ε   = (E_m11, E_m22, 2 E_m12)        Voigt strain, weft = material x
//   K   = [[kxx, kxy, 0], [kxy, kyy, 0], [0, 0, kss]]
//   φ   = material angle: weft axis measured from the lab x axis (0 weft, π/4 bias, π/2 warp)
//
// Stresses (derivation in inplane_material.cpp):
//   S_m = [[kxx ε1 + kxy ε2, kss ε3], [kss ε3, kxy ε1 + kyy ε2]],  S = R S_m Rᵀ  (2nd PK, StVK)
//   P   = F S + f'(J) ∂J/∂F,   f(J) = kn1 (J − 1)² + kn2 log² J                       (3.23)
//
// Two kinematic settings share the law:
// * planar F (2×2): J = det F, signed. An inverted element (J ≤ 0) has Ψ = +∞ when kn2 ≠ 0
//   (the log barrier; pk1/dpk1 then return zeros and callers check validity); with kn2 = 0
//   the log term is absent and (J − 1)² is evaluated with the signed J, as in plain StVK.
// * surface F (3×2, a triangle embedded in 3-D): C = FᵀF, J = √det C ≥ 0, and ∂J/∂F =
//   F adj(C)/J. At J = 0 (a degenerate triangle) Ψ is +∞ when kn2 ≠ 0; with kn2 = 0 the
//   value is finite but √det C is not differentiable, so the area term's derivatives are
//   dropped there (never NaN).
//
// The "stiffening" model adds the lock-up terms (lockup_curve.hpp) on three strain measures
// of the material frame, each zero for a non-positive argument:
//   Ψ += φ_x(u_x) + φ_y(u_y) + φ_s(u_s),  u_x = ε1 + axx ε2,  u_y = ε2 + ayy ε1,  u_s = |ε3|
// so, with n_d = ∂u_d/∂ε (Voigt), the material-frame stress gains Σ_d φ_d'(u_d) n_d and the
// tangent Σ_d φ_d''(u_d) n_d n_dᵀ: convex in ε, and the StVK stress S = R S_m Rᵀ above becomes
// nonlinear in E. A lateral share a > 0 lets a narrowing across the pull relieve the lock-up,
// so the lock-up also pulls the width in. With l = 0 the terms vanish and the law is exactly
// eq. 6.1.
//
// The law is linear in every parameter except the lock-up rates b and shares a;
// parameter_derivative() builds the law whose Ψ is ∂Ψ/∂p_k, which the fit's sensitivities use
// (see MembraneTerm::add_gradient_per_parameter). For a share that law is φ'(u) w, w the
// other normal strain (ε2 for axx), whose tangent needs φ'''.

#include <Eigen/Core>

#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/energies/lockup_curve.hpp"

namespace yarnfit::shell {

class InplaneMaterial {
 public:
  // `material_angle`: weft axis angle from the lab x axis [rad].
  InplaneMaterial(const InplaneParams& p, double material_angle);

  // The law whose Ψ, P and ∂P/∂F are the derivatives of this law's with respect to parameter
  // k (the order of k_inplane_param_names) at `p`.
  [[nodiscard]] static InplaneMaterial parameter_derivative(const InplaneParams& p, double material_angle, int k);

  // Planar 2×2 deformation gradient in the lab frame; J = det F (signed).
  // Energy density [J/m²]: +∞ when J ≤ 0 and kn2 ≠ 0; never NaN for finite F.
  [[nodiscard]] double psi(const Eigen::Matrix2d& F) const;
  // First Piola-Kirchhoff stress ∂Ψ/∂F [N/m]; zeros where Ψ = +∞.
  [[nodiscard]] Eigen::Matrix2d pk1(const Eigen::Matrix2d& F) const;
  // ∂²Ψ/∂F∂F, rows and columns indexed by vec(F) column-major: (F00, F10, F01, F11).
  [[nodiscard]] Eigen::Matrix4d dpk1(const Eigen::Matrix2d& F) const;

  // Surface 3×2 deformation gradient of a triangle in 3-D; J = √det(FᵀF).
  // (Named apart from the planar overloads so that Eigen expressions convert unambiguously.)
  [[nodiscard]] double psi_surface(const Eigen::Matrix<double, 3, 2>& F) const;
  [[nodiscard]] Eigen::Matrix<double, 3, 2> pk1_surface(const Eigen::Matrix<double, 3, 2>& F) const;
  // 6×6, vec(F) column-major: (F00, F10, F20, F01, F11, F21).
  [[nodiscard]] Eigen::Matrix<double, 6, 6> dpk1_surface(
      const Eigen::Matrix<double, 3, 2>& F) const;

  [[nodiscard]] const InplaneParams& params() const { return m_params; }
  [[nodiscard]] double material_angle() const { return m_material_angle; }

  // Second Piola-Kirchhoff stress of the StVK part in the lab frame, S = R 𝕂(Rᵀ E R) Rᵀ,
  // for a symmetric lab-frame strain E. Linear in E.
  [[nodiscard]] Eigen::Matrix2d stvk_stress(const Eigen::Matrix2d& E) const;
  // The StVK part plus the lock-up terms (the whole second Piola-Kirchhoff stress but the
  // area terms), and its directional derivative dS for a strain increment dE at E.
  [[nodiscard]] Eigen::Matrix2d strain_stress(const Eigen::Matrix2d& E) const;
  [[nodiscard]] Eigen::Matrix2d strain_stress_direction(const Eigen::Matrix2d& E, const Eigen::Matrix2d& dE) const;
  // ½ εᵀKε plus the lock-up energies at the lab-frame strain E [J/m²].
  [[nodiscard]] double strain_energy(const Eigen::Matrix2d& E) const;

 private:
  // True when the log-barrier term is present (kn2 ≠ 0): the domain is then J > 0.
  [[nodiscard]] bool has_barrier() const { return m_params.kn2 != 0.0; }
  // f(J), f'(J), f''(J) of the area term; J > 0 when has_barrier().
  [[nodiscard]] double area_energy(double J) const;
  [[nodiscard]] double area_d1(double J) const;
  [[nodiscard]] double area_d2(double J) const;

  [[nodiscard]] bool has_lockup() const {
    return m_lockup[0].active() || m_lockup[1].active() || m_lockup[2].active();
  }
  // The lock-up terms on the material-frame Voigt strain e: energy, stress (∂/∂e; the third
  // entry is S_m12) and tangent (∂²/∂e²). In a share's sensitivity law (m_share_derivative ≥ 0)
  // they are those of φ'(u) w instead.
  [[nodiscard]] double lockup_energy(const Eigen::Vector3d& e) const;
  [[nodiscard]] Eigen::Vector3d lockup_stress(const Eigen::Vector3d& e) const;
  [[nodiscard]] Eigen::Matrix3d lockup_tangent(const Eigen::Vector3d& e) const;

  InplaneParams m_params;
  // Lock-up of the weft (u_x), warp (u_y) and shear (u_s) measures.
  LockupCurve m_lockup[3];
  // ∂u_x/∂ε and ∂u_y/∂ε: (1, axx, 0) and (ayy, 1, 0).
  Eigen::Vector3d m_lockup_normal[2];
  // −1, or the curve (0 weft, 1 warp) whose lateral share this sensitivity law differentiates.
  int m_share_derivative = -1;
  double m_material_angle = 0.0;
  Eigen::Matrix2d m_rotation;  // columns: weft and warp axes in the lab frame
};

}  // namespace yarnfit::shell
