#include "shell_fit/energies/inplane_material.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace yarnfit::shell {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// adj(M) = det(M) M⁻¹ for a 2×2 matrix, defined also where M is singular.
Eigen::Matrix2d adjugate(const Eigen::Matrix2d& m) {
  Eigen::Matrix2d a;
  a << m(1, 1), -m(0, 1), -m(1, 0), m(0, 0);
  return a;
}

double det2(const Eigen::Matrix2d& m) { return m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0); }

double contract(const Eigen::Matrix2d& a, const Eigen::Matrix2d& b) {
  return a.cwiseProduct(b).sum();
}

// Directional derivative of the first Piola-Kirchhoff stress P = F S(E) (StVK and lock-up):
//   dP = dF S + F dS(E; dE),  dE = ½ (dFᵀ F + Fᵀ dF).
// Written once for 2×2 and 3×2 F; the caller fills one column of ∂P/∂F per basis direction.
template <int Rows>
Eigen::Matrix<double, Rows, 2> stvk_pk1_direction(const InplaneMaterial& m,
                                                  const Eigen::Matrix<double, Rows, 2>& F,
                                                  const Eigen::Matrix2d& E, const Eigen::Matrix2d& S,
                                                  const Eigen::Matrix<double, Rows, 2>& dF) {
  const Eigen::Matrix2d dFtF = dF.transpose() * F;
  const Eigen::Matrix2d dE = 0.5 * (dFtF + dFtF.transpose());
  return dF * S + F * m.strain_stress_direction(E, dE);
}

}  // namespace

InplaneMaterial::InplaneMaterial(const InplaneParams& p, double material_angle)
    : m_params(p),
      m_lockup{{p.lxx, p.bxx, false}, {p.lyy, p.byy, false}, {p.lss, p.bss, false}},
      m_lockup_normal{{1.0, p.axx, 0.0}, {p.ayy, 1.0, 0.0}},
      m_material_angle(material_angle) {
  const double c = std::cos(material_angle);
  const double s = std::sin(material_angle);
  m_rotation << c, -s, s, c;
}

InplaneMaterial InplaneMaterial::parameter_derivative(const InplaneParams& p, double material_angle, int k) {
  // Ψ is linear in every parameter but the rates and shares: ∂Ψ/∂p_k is the law with p_k = 1
  // and the other linear parameters 0 (a lock-up stiffness keeps its curve's rate and share).
  // For a rate or a share it is that lock-up curve alone, in its derivative form.
  std::array<double, k_inplane_param_count> v{};
  const auto full = to_array(p);
  if (!enters_linearly(k) || k >= k_first_lockup_param) {
    const int curve = lockup_curve_of(k);
    const auto l_index = static_cast<std::size_t>(k_first_lockup_param + 2 * curve);
    v[l_index] = enters_linearly(k) ? 1.0 : full[l_index];
    v[l_index + 1] = full[l_index + 1];
    if (curve < 2) {
      const auto a_index = static_cast<std::size_t>(k_first_share_param + curve);
      v[a_index] = full[a_index];
    }
  } else {
    v[static_cast<std::size_t>(k)] = 1.0;
  }
  InplaneMaterial m(inplane_from_array(v), material_angle);
  if (is_lockup_rate(k)) m.m_lockup[lockup_curve_of(k)].rate_derivative = true;
  if (is_lockup_share(k)) m.m_share_derivative = lockup_curve_of(k);
  return m;
}

namespace {

// The material-frame Voigt strain (ε1, ε2, ε3 = 2 E_m12) of a lab-frame strain.
Eigen::Vector3d voigt(const Eigen::Matrix2d& R, const Eigen::Matrix2d& E) {
  const Eigen::Matrix2d Em = R.transpose() * E * R;
  return {Em(0, 0), Em(1, 1), Em(0, 1) + Em(1, 0)};
}

// A material-frame stress (S11, S22, S12) as a lab-frame matrix.
Eigen::Matrix2d lab_stress(const Eigen::Matrix2d& R, double s11, double s22, double s12) {
  Eigen::Matrix2d Sm;
  Sm << s11, s12, s12, s22;
  return R * Sm * R.transpose();
}

}  // namespace

double InplaneMaterial::lockup_energy(const Eigen::Vector3d& e) const {
  const double u[3] = {m_lockup_normal[0].dot(e), m_lockup_normal[1].dot(e), std::abs(e[2])};
  if (m_share_derivative >= 0) {
    const int d = m_share_derivative;
    return m_lockup[d].stress(u[d]) * e[1 - d];  // φ'(u) w, w = ε2 for the weft, ε1 for the warp
  }
  return m_lockup[0].energy(u[0]) + m_lockup[1].energy(u[1]) + m_lockup[2].energy(u[2]);
}

Eigen::Vector3d InplaneMaterial::lockup_stress(const Eigen::Vector3d& e) const {
  const double u[3] = {m_lockup_normal[0].dot(e), m_lockup_normal[1].dot(e), std::abs(e[2])};
  if (m_share_derivative >= 0) {
    // ∂(φ'(u) w)/∂e = φ''(u) w n + φ'(u) ∂w/∂e.
    const int d = m_share_derivative;
    Eigen::Vector3d s = m_lockup[d].tangent(u[d]) * e[1 - d] * m_lockup_normal[d];
    s[1 - d] += m_lockup[d].stress(u[d]);
    return s;
  }
  Eigen::Vector3d s = m_lockup[0].stress(u[0]) * m_lockup_normal[0] + m_lockup[1].stress(u[1]) * m_lockup_normal[1];
  s[2] += std::copysign(m_lockup[2].stress(u[2]), e[2]);
  return s;
}

Eigen::Matrix3d InplaneMaterial::lockup_tangent(const Eigen::Vector3d& e) const {
  const double u[3] = {m_lockup_normal[0].dot(e), m_lockup_normal[1].dot(e), std::abs(e[2])};
  if (m_share_derivative >= 0) {
    // φ'''(u) w n nᵀ + φ''(u) (n ∂wᵀ + ∂w nᵀ).
    const int d = m_share_derivative;
    const Eigen::Vector3d& n = m_lockup_normal[d];
    Eigen::Vector3d dw = Eigen::Vector3d::Zero();
    dw[1 - d] = 1.0;
    const double t = m_lockup[d].tangent(u[d]);
    return m_lockup[d].third(u[d]) * e[1 - d] * n * n.transpose() + t * (n * dw.transpose() + dw * n.transpose());
  }
  Eigen::Matrix3d T = m_lockup[0].tangent(u[0]) * m_lockup_normal[0] * m_lockup_normal[0].transpose() +
                      m_lockup[1].tangent(u[1]) * m_lockup_normal[1] * m_lockup_normal[1].transpose();
  T(2, 2) += m_lockup[2].tangent(u[2]);
  return T;
}

Eigen::Matrix2d InplaneMaterial::strain_stress(const Eigen::Matrix2d& E) const {
  Eigen::Matrix2d S = stvk_stress(E);
  if (!has_lockup()) return S;
  const Eigen::Vector3d s = lockup_stress(voigt(m_rotation, E));
  return S + lab_stress(m_rotation, s[0], s[1], s[2]);
}

Eigen::Matrix2d InplaneMaterial::strain_stress_direction(const Eigen::Matrix2d& E, const Eigen::Matrix2d& dE) const {
  Eigen::Matrix2d dS = stvk_stress(dE);
  if (!has_lockup()) return dS;
  const Eigen::Vector3d ds = lockup_tangent(voigt(m_rotation, E)) * voigt(m_rotation, dE);
  return dS + lab_stress(m_rotation, ds[0], ds[1], ds[2]);
}

double InplaneMaterial::strain_energy(const Eigen::Matrix2d& E) const {
  // ½ εᵀKε = ½ S_m : E_m = ½ S : E (the rotation preserves the contraction).
  double psi = 0.5 * contract(stvk_stress(E), E);
  if (has_lockup()) psi += lockup_energy(voigt(m_rotation, E));
  return psi;
}

Eigen::Matrix2d InplaneMaterial::stvk_stress(const Eigen::Matrix2d& E) const {
  const Eigen::Matrix2d Em = m_rotation.transpose() * E * m_rotation;
  const double e1 = Em(0, 0);
  const double e2 = Em(1, 1);
  const double e3 = Em(0, 1) + Em(1, 0);  // engineering shear 2 E_m12
  // S_m = ∂(½ εᵀKε)/∂E_m; the shear entry is kss ε3 on both off-diagonals because ε3 counts
  // E_m12 and E_m21 once each.
  Eigen::Matrix2d Sm;
  Sm(0, 0) = m_params.kxx * e1 + m_params.kxy * e2;
  Sm(1, 1) = m_params.kxy * e1 + m_params.kyy * e2;
  Sm(0, 1) = Sm(1, 0) = m_params.kss * e3;
  return m_rotation * Sm * m_rotation.transpose();
}

double InplaneMaterial::area_energy(double J) const {
  double f = m_params.kn1 * (J - 1.0) * (J - 1.0);
  if (has_barrier()) {
    const double l = std::log(J);
    f += m_params.kn2 * l * l;
  }
  return f;
}

double InplaneMaterial::area_d1(double J) const {
  double d = 2.0 * m_params.kn1 * (J - 1.0);
  if (has_barrier()) d += 2.0 * m_params.kn2 * std::log(J) / J;
  return d;
}

double InplaneMaterial::area_d2(double J) const {
  double d = 2.0 * m_params.kn1;
  if (has_barrier()) d += 2.0 * m_params.kn2 * (1.0 - std::log(J)) / (J * J);
  return d;
}

// ---- planar F (2×2), J = det F ---------------------------------------------------------

double InplaneMaterial::psi(const Eigen::Matrix2d& F) const {
  const double J = det2(F);
  if (has_barrier() && !(J > 0.0)) return infinity;
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  return strain_energy(E) + area_energy(J);
}

Eigen::Matrix2d InplaneMaterial::pk1(const Eigen::Matrix2d& F) const {
  const double J = det2(F);
  if (has_barrier() && !(J > 0.0)) return Eigen::Matrix2d::Zero();
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  // ∂J/∂F = cof(F) = adj(F)ᵀ
  return F * strain_stress(E) + area_d1(J) * adjugate(F).transpose();
}

Eigen::Matrix4d InplaneMaterial::dpk1(const Eigen::Matrix2d& F) const {
  const double J = det2(F);
  if (has_barrier() && !(J > 0.0)) return Eigen::Matrix4d::Zero();
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d S = strain_stress(E);
  Eigen::Matrix4d D;
  for (int c = 0; c < 4; ++c) {
    Eigen::Matrix2d dF = Eigen::Matrix2d::Zero();
    dF(c % 2, c / 2) = 1.0;
    const Eigen::Matrix2d dP = stvk_pk1_direction<2>(*this, F, E, S, dF);
    D.col(c) = Eigen::Map<const Eigen::Vector4d>(dP.data());
  }
  // Area term: f''(J) ∂J⊗∂J + f'(J) ∂²J, with vec(cof F) = (F11, −F01, −F10, F00) and ∂²J
  // pairing F00 with F11 (+1) and F10 with F01 (−1).
  const Eigen::Vector4d g(F(1, 1), -F(0, 1), -F(1, 0), F(0, 0));
  D.noalias() += area_d2(J) * g * g.transpose();
  const double d1 = area_d1(J);
  D(0, 3) += d1;
  D(3, 0) += d1;
  D(1, 2) -= d1;
  D(2, 1) -= d1;
  return D;
}

// ---- surface F (3×2), J = √det C ------------------------------------------------------

double InplaneMaterial::psi_surface(const Eigen::Matrix<double, 3, 2>& F) const {
  const Eigen::Matrix2d C = F.transpose() * F;
  const double J = std::sqrt(std::max(det2(C), 0.0));
  if (has_barrier() && !(J > 0.0)) return infinity;
  const Eigen::Matrix2d E = 0.5 * (C - Eigen::Matrix2d::Identity());
  return strain_energy(E) + area_energy(J);
}

Eigen::Matrix<double, 3, 2> InplaneMaterial::pk1_surface(
    const Eigen::Matrix<double, 3, 2>& F) const {
  const Eigen::Matrix2d C = F.transpose() * F;
  const double J = std::sqrt(std::max(det2(C), 0.0));
  if (has_barrier() && !(J > 0.0)) return Eigen::Matrix<double, 3, 2>::Zero();
  const Eigen::Matrix2d E = 0.5 * (C - Eigen::Matrix2d::Identity());
  Eigen::Matrix2d T = strain_stress(E);
  // ∂J/∂F = F adj(C)/J (from 2J dJ = d det C = adj(C) : dC, dC = 2 sym(Fᵀ dF)).
  if (J > 0.0) T += (area_d1(J) / J) * adjugate(C);
  return F * T;
}

Eigen::Matrix<double, 6, 6> InplaneMaterial::dpk1_surface(
    const Eigen::Matrix<double, 3, 2>& F) const {
  using Matrix32 = Eigen::Matrix<double, 3, 2>;
  const Eigen::Matrix2d C = F.transpose() * F;
  const double J = std::sqrt(std::max(det2(C), 0.0));
  if (has_barrier() && !(J > 0.0)) return Eigen::Matrix<double, 6, 6>::Zero();
  const Eigen::Matrix2d E = 0.5 * (C - Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d S = strain_stress(E);
  const bool area_smooth = J > 0.0;
  const Eigen::Matrix2d adjC = adjugate(C);
  // P_area = F T with T = (f'/J) adj(C):
  //   dT = (f''/J − f'/J²) dJ adj(C) + (f'/J) adj(dC),  dJ = adj(C) : dC / (2J).
  const double t = area_smooth ? area_d1(J) / J : 0.0;
  const double dt_dJ = area_smooth ? (area_d2(J) - t) / J : 0.0;
  Eigen::Matrix<double, 6, 6> D;
  for (int c = 0; c < 6; ++c) {
    Matrix32 dF = Matrix32::Zero();
    dF(c % 3, c / 3) = 1.0;
    Matrix32 dP = stvk_pk1_direction<3>(*this, F, E, S, dF);
    if (area_smooth) {
      const Eigen::Matrix2d dFtF = dF.transpose() * F;
      const Eigen::Matrix2d dC = dFtF + dFtF.transpose();
      const double dJ = contract(adjC, dC) / (2.0 * J);
      const Eigen::Matrix2d dT = dt_dJ * dJ * adjC + t * adjugate(dC);
      dP += dF * (t * adjC) + F * dT;
    }
    D.col(c) = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(dP.data());
  }
  return D;
}

}  // namespace yarnfit::shell
