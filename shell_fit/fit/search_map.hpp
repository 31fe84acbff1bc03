#pragma once
// The variables the in-plane fit searches (inplane_fit.cpp): one slot q_j per free parameter
// and the map p(q) with its Jacobian ∂p/∂q, which turns the scenes' exact ∂r/∂p into the
// Jacobian Ceres needs.
//
// A slot holds
// * log p for a stiffness (kxx kyy kss kn1 kn2, and kxy of the thesis law),
// * p itself for a parameter searched linearly: the lock-up rates b and shares a (0 is a natural
//   value of both), and, in the stiffening law, kxy (with the shares it often wants 0, which a
//   log-space search only creeps towards),
// * for a lock-up pair (l, b) of the stiffening law searched together, the lock-up stress at
//   the direction's reference strain x_r (the Green strain that ends its fitted range),
//     σ = φ'(x_r) = l x_r² h_2(b x_r),   l = σ / g(b),   g(b) = x_r² h_2(b x_r),
//   searched linearly from 0 (no lock-up). Over a fitted range a faster rate with a smaller l
//   gives nearly the same curve; in (l, b) that is a long curved valley the fit crept along
//   (docs/shell-fit.md). At fixed σ a change of b only changes the curve's shape, and the
//   fit converges.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

// Whether parameter k's slot holds log p (see above; not for a lock-up stress slot).
bool searched_in_log(int k, InplaneModel model);

class SearchMap {
 public:
  using Params = Eigen::Matrix<double, k_inplane_param_count, 1>;

  // `free`: the searched parameters (indices into k_inplane_param_names), in slot order;
  // `held`: the values of the others; `x_ref`: the reference strain of the weft, warp and shear
  // lock-up curves (> 0).
  SearchMap(std::vector<int> free, const Params& held, InplaneModel model, const std::array<double, 3>& x_ref);

  [[nodiscard]] const std::vector<int>& free() const { return m_free; }
  [[nodiscard]] std::size_t size() const { return m_free.size(); }
  [[nodiscard]] bool log_slot(std::size_t j) const;
  // The lock-up curve (0 weft, 1 warp, 2 shear) whose stress slot j is, or −1.
  [[nodiscard]] int stress_curve(std::size_t j) const;
  // g(b) of a curve: σ = l g(b).
  [[nodiscard]] double stress_factor(int curve, double b) const;

  [[nodiscard]] Params params(const double* q) const;
  [[nodiscard]] std::vector<double> q_of(const Params& p) const;
  // ∂p/∂q (parameters × slots) at q.
  [[nodiscard]] Eigen::MatrixXd jacobian(const double* q) const;

 private:
  std::vector<int> m_free;
  Params m_held;
  InplaneModel m_model;
  std::array<double, 3> m_x_ref;
  std::array<int, k_inplane_param_count> m_slot_of;  // −1: held
};

}  // namespace yarnfit::shell
