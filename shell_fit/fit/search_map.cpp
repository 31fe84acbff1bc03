#include "shell_fit/fit/search_map.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "shell_fit/energies/lockup_curve.hpp"

namespace yarnfit::shell {

namespace {

bool is_lockup_stiffness(int k) { return k == 6 || k == 8 || k == 10; }

}  // namespace

bool searched_in_log(int k, InplaneModel model) {
  if (model == InplaneModel::stiffening && (k == 1 || is_lockup_stiffness(k))) return false;
  return enters_linearly(k);
}

SearchMap::SearchMap(std::vector<int> free, const Params& held, InplaneModel model, const std::array<double, 3>& x_ref)
    : m_free(std::move(free)), m_held(held), m_model(model), m_x_ref(x_ref) {
  m_slot_of.fill(-1);
  for (std::size_t j = 0; j < m_free.size(); ++j) m_slot_of[static_cast<std::size_t>(m_free[j])] = static_cast<int>(j);
}

bool SearchMap::log_slot(std::size_t j) const { return stress_curve(j) < 0 && searched_in_log(m_free[j], m_model); }

int SearchMap::stress_curve(std::size_t j) const {
  const int k = m_free[j];
  if (m_model != InplaneModel::stiffening || !is_lockup_stiffness(k)) return -1;
  return m_slot_of[static_cast<std::size_t>(k + 1)] >= 0 ? (k - k_first_lockup_param) / 2 : -1;
}

double SearchMap::stress_factor(int curve, double b) const {
  const double x = m_x_ref[static_cast<std::size_t>(curve)];
  return x * x * lockup_h(2, b * x);
}

SearchMap::Params SearchMap::params(const double* q) const {
  Params p = m_held;
  for (std::size_t j = 0; j < size(); ++j) p[m_free[j]] = log_slot(j) ? std::exp(q[j]) : q[j];
  // The rates are set above, so each l can be read off its stress.
  for (std::size_t j = 0; j < size(); ++j)
    if (const int c = stress_curve(j); c >= 0) p[m_free[j]] = q[j] / stress_factor(c, p[m_free[j] + 1]);
  return p;
}

std::vector<double> SearchMap::q_of(const Params& p) const {
  std::vector<double> q(size());
  for (std::size_t j = 0; j < size(); ++j) {
    const int k = m_free[j];
    if (const int c = stress_curve(j); c >= 0) q[j] = p[k] * stress_factor(c, p[k + 1]);
    else q[j] = log_slot(j) ? std::log(std::max(p[k], 1e-300)) : p[k];
  }
  return q;
}

Eigen::MatrixXd SearchMap::jacobian(const double* q) const {
  const Params p = params(q);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(k_inplane_param_count, static_cast<Eigen::Index>(size()));
  for (std::size_t j = 0; j < size(); ++j) {
    const int k = m_free[j];
    const auto jj = static_cast<Eigen::Index>(j);
    if (const int c = stress_curve(j); c >= 0) {
      // l = σ/g(b): ∂l/∂σ = 1/g, and ∂l/∂b = −l g'(b)/g(b) = −l x h_2'(bx)/h_2(bx) in b's column.
      const double b = p[k + 1], x = m_x_ref[static_cast<std::size_t>(c)];
      D(k, jj) = 1.0 / stress_factor(c, b);
      D(k, m_slot_of[static_cast<std::size_t>(k + 1)]) += -p[k] * x * lockup_dh(2, b * x) / lockup_h(2, b * x);
    } else {
      D(k, jj) += log_slot(j) ? p[k] : 1.0;
    }
  }
  return D;
}

}  // namespace yarnfit::shell
