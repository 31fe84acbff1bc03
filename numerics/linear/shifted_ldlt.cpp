#include "numerics/linear/shifted_ldlt.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace yarnfit::numerics {

void ShiftedLdlt::assemble(int n, Triplets& lower) {
  for (int i = 0; i < n; ++i) lower.emplace_back(i, i, 0.0);
  if (n == m_n && same_triplet_sequence(lower)) {
    // The same (row, column) sequence as last time: scatter the values into the known slots,
    // first occurrence assigned and later ones added in triplet order, as setFromTriplets does.
    double* values = m_matrix.valuePtr();
    for (std::size_t k = 0; k < lower.size(); ++k) {
      const int slot = m_triplet_slot[k];
      if (slot < 0) values[-slot - 1] = lower[k].value();
      else values[slot] += lower[k].value();
    }
    ++m_scattered;
  } else {
    m_n = n;
    m_matrix.resize(n, n);
    m_matrix.setFromTriplets(lower.begin(), lower.end());
    remember_triplet_slots(lower);
  }
  m_base.assign(m_matrix.valuePtr(), m_matrix.valuePtr() + m_matrix.nonZeros());
  // Sorted column-major lower triangle: each column's diagonal is its first entry.
  double sum = 0.0;
  for (int j = 0; j < n; ++j) sum += std::abs(m_base[static_cast<std::size_t>(m_matrix.outerIndexPtr()[j])]);
  m_scale = n > 0 ? sum / n : 1.0;
  if (!(m_scale > 0.0)) m_scale = 1.0;  // an all-zero diagonal: shifts relative to 1
}

bool ShiftedLdlt::same_triplet_sequence(const Triplets& lower) const {
  if (lower.size() != m_triplet_rows.size()) return false;
  for (std::size_t k = 0; k < lower.size(); ++k)
    if (lower[k].row() != m_triplet_rows[k] || lower[k].col() != m_triplet_cols[k]) return false;
  return true;
}

void ShiftedLdlt::remember_triplet_slots(const Triplets& lower) {
  // Column by column rather than a binary search per triplet: the triplets are grouped by
  // column (a stable counting sort, so each slot's triplets keep their order), each column's
  // stored rows are marked with their slots once, and every triplet reads its slot from the
  // mark. Linear in triplets and entries; a contact entering or leaving calls this again.
  const std::size_t count = lower.size();
  m_triplet_rows.resize(count);
  m_triplet_cols.resize(count);
  m_triplet_slot.resize(count);
  const int* outer = m_matrix.outerIndexPtr();
  const int* inner = m_matrix.innerIndexPtr();
  std::vector<int> start(static_cast<std::size_t>(m_n) + 1, 0);
  for (std::size_t k = 0; k < count; ++k) {
    m_triplet_rows[k] = lower[k].row();
    m_triplet_cols[k] = lower[k].col();
    ++start[static_cast<std::size_t>(m_triplet_cols[k]) + 1];
  }
  for (int c = 0; c < m_n; ++c) start[static_cast<std::size_t>(c) + 1] += start[static_cast<std::size_t>(c)];
  std::vector<int> by_column(count);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < count; ++k)
    by_column[static_cast<std::size_t>(next[static_cast<std::size_t>(m_triplet_cols[k])]++)] = static_cast<int>(k);
  std::vector<int> slot_of_row(static_cast<std::size_t>(m_n), -1);
  std::vector<char> seen(static_cast<std::size_t>(m_matrix.nonZeros()), 0);
  for (int c = 0; c < m_n; ++c) {
    for (int p = outer[c]; p < outer[c + 1]; ++p) slot_of_row[static_cast<std::size_t>(inner[p])] = p;
    for (int q = start[static_cast<std::size_t>(c)]; q < start[static_cast<std::size_t>(c) + 1]; ++q) {
      const auto k = static_cast<std::size_t>(by_column[static_cast<std::size_t>(q)]);
      const int slot = slot_of_row[static_cast<std::size_t>(m_triplet_rows[k])];
      // Encoded as −slot − 1 for the slot's first triplet (assigned), slot for the others (added).
      m_triplet_slot[k] = seen[static_cast<std::size_t>(slot)] ? slot : -slot - 1;
      seen[static_cast<std::size_t>(slot)] = 1;
    }
  }
}

double ShiftedLdlt::relative_min_diagonal() const {
  double lowest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < m_n; ++j) lowest = std::min(lowest, m_base[static_cast<std::size_t>(m_matrix.outerIndexPtr()[j])]);
  return lowest / m_scale;
}

bool ShiftedLdlt::same_pattern() const {
  return !m_outer.empty() && m_outer.size() == static_cast<std::size_t>(m_n + 1) &&
         m_inner.size() == static_cast<std::size_t>(m_matrix.nonZeros()) &&
         std::equal(m_outer.begin(), m_outer.end(), m_matrix.outerIndexPtr()) &&
         std::equal(m_inner.begin(), m_inner.end(), m_matrix.innerIndexPtr());
}

bool ShiftedLdlt::factorise(double shift) {
  double* values = m_matrix.valuePtr();
  std::copy(m_base.begin(), m_base.end(), values);
  const double alpha = shift * m_scale;
  for (int j = 0; j < m_n; ++j) values[m_matrix.outerIndexPtr()[j]] += alpha;
  if (!same_pattern()) {
    m_solver.analyzePattern(m_matrix);
    m_outer.assign(m_matrix.outerIndexPtr(), m_matrix.outerIndexPtr() + m_n + 1);
    m_inner.assign(m_matrix.innerIndexPtr(), m_matrix.innerIndexPtr() + m_matrix.nonZeros());
    ++m_analyses;
  }
  m_solver.factorize(m_matrix);
  m_negative_pivots = -1;
  if (m_solver.info() != Eigen::Success) return false;
  const auto d = m_solver.vectorD();
  if (!d.allFinite() || (d.array() == 0.0).any()) return false;
  m_negative_pivots = static_cast<int>((d.array() < 0.0).count());
  // A positive D makes LDLᵀ positive definite, so the solve gives a descent direction.
  return m_negative_pivots == 0;
}

bool positive_definite_on_constraints(const ShiftedLdlt& k, const Eigen::MatrixXd& c, Eigen::MatrixXd* y) {
  const int negative = k.negative_pivots();
  if (negative < 0 || negative > c.rows()) return false;
  Eigen::MatrixXd local;
  Eigen::MatrixXd& ky = y != nullptr ? *y : local;
  ky = k.solve(Eigen::MatrixXd(c.transpose()));
  const Eigen::MatrixXd schur = c * ky;
  if (!schur.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (schur + schur.transpose()), Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return false;
  const Eigen::VectorXd lambda = eig.eigenvalues();
  // A Schur eigenvalue at the rounding of zero would make the count a coin toss: not trusted.
  const double noise = 1e-12 * lambda.cwiseAbs().maxCoeff();
  if ((lambda.array().abs() <= noise).any()) return false;
  return (lambda.array() < 0.0).count() == negative;
}

Eigen::MatrixXd solve_constrained(const ShiftedLdlt& k, const Eigen::MatrixXd* c, const Eigen::LDLT<Eigen::MatrixXd>* cct,
                                  const Eigen::MatrixXd& rhs) {
  Eigen::MatrixXd z = k.solve(rhs);
  if (c == nullptr || c->rows() == 0) return z;
  const Eigen::MatrixXd y = k.solve(Eigen::MatrixXd(c->transpose()));
  const Eigen::MatrixXd schur = *c * y;
  z -= y * schur.ldlt().solve(*c * z);
  // Keep Z exactly feasible: remove the round-off part of C Z.
  if (cct != nullptr) z -= c->transpose() * cct->solve(*c * z);
  return z;
}

ConstrainedSolver::ConstrainedSolver(const ShiftedLdlt& k, const Eigen::MatrixXd& c)
    : m_k(k), m_c(c), m_y(k.solve(Eigen::MatrixXd(c.transpose()))), m_schur(c * m_y), m_cct(c * c.transpose()) {}

Eigen::MatrixXd ConstrainedSolver::solve(const Eigen::MatrixXd& rhs) const {
  Eigen::MatrixXd z = m_k.solve(rhs);
  if (m_c.rows() == 0) return z;
  z -= m_y * m_schur.solve(m_c * z);
  z -= m_c.transpose() * m_cct.solve(m_c * z);
  return z;
}

}  // namespace yarnfit::numerics
