#pragma once
// The sparse symmetric factorisation of the Newton solver (newton_solver.hpp) and of the
// sensitivities at an equilibrium (yarn_fit/homogenise/sensitivity.hpp): the lower triangle
// of H with an explicit diagonal, factorised as H + μ·d̄·I (d̄ the mean |diagonal|, so μ is
// unit-free) by Eigen's simplicial LDLᵀ, the fastest factorisation available here for the
// tiles' Hessians.
//
// Kept between solves of the same system, it saves work that depends only on the sparsity
// pattern: the fill-reducing ordering and elimination tree (redone only when the pattern
// changes, i.e. when a contact pair enters or leaves), and the sort of the triplets (when
// they arrive in the same (row, column) sequence as last time, their values are scattered
// straight into the matrix, summed in triplet order as Eigen's setFromTriplets sums
// duplicates, so the matrix is bitwise the one a fresh assembly builds).

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

#include "numerics/terms/energy_term.hpp"

namespace yarnfit::numerics {

class ShiftedLdlt {
 public:
  // Builds the matrix from `lower` (row ≥ column, duplicates summed in order) plus zeros on
  // the diagonal (appended to `lower`).
  void assemble(int n, Triplets& lower);
  // Smallest diagonal entry relative to d̄: a matrix with a non-positive diagonal entry
  // cannot be positive definite.
  [[nodiscard]] double relative_min_diagonal() const;
  // Factorises H + shift·d̄·I; false if that is not positive definite.
  bool factorise(double shift);
  // After factorise: the number of negative pivots of D (the negative eigenvalues of the
  // shifted matrix, by Sylvester's law of inertia), or −1 when the factorisation broke down.
  [[nodiscard]] int negative_pivots() const { return m_negative_pivots; }
  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const { return m_solver.solve(rhs); }
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const { return m_solver.solve(rhs); }
  [[nodiscard]] int size() const { return m_n; }
  [[nodiscard]] double mean_diagonal() const { return m_scale; }
  // Symbolic analyses and assemblies that took the fast path (same triplet pattern), since
  // construction.
  [[nodiscard]] int analyses() const { return m_analyses; }
  [[nodiscard]] int scattered_assemblies() const { return m_scattered; }

 private:
  [[nodiscard]] bool same_pattern() const;
  [[nodiscard]] bool same_triplet_sequence(const Triplets& lower) const;
  void remember_triplet_slots(const Triplets& lower);

  int m_n = 0;
  Eigen::SparseMatrix<double> m_matrix;  // column-major lower triangle
  std::vector<double> m_base;            // unshifted values
  double m_scale = 1.0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> m_solver;
  std::vector<int> m_outer, m_inner;  // the analysed pattern
  // The last assembly's triplet sequence and the value slot of each triplet.
  std::vector<int> m_triplet_rows, m_triplet_cols, m_triplet_slot;
  int m_analyses = 0;
  int m_scattered = 0;
  int m_negative_pivots = -1;
};

// Solves the equality-constrained system  [K Cᵀ; C 0] [Z; Λ] = [B; 0]  for every column of B
// by the Schur complement on C's few dense rows, with K the factorised matrix:
//   K Z0 = B,  K Y = Cᵀ,  Λ = (C Y)⁻¹ C Z0,  Z = Z0 − Y Λ,
// and the round-off part of C Z removed (cct: an LDLᵀ of C Cᵀ). Z minimises ½zᵀKz − bᵀz on
// C z = 0. Without constraints (c null or empty) Z = K⁻¹ B.
Eigen::MatrixXd solve_constrained(const ShiftedLdlt& k, const Eigen::MatrixXd* c, const Eigen::LDLT<Eigen::MatrixXd>* cct,
                                  const Eigen::MatrixXd& rhs);

// True when K (factorised, possibly indefinite) is positive definite on C z = 0, so that the
// constrained solve below minimises a convex quadratic there. By the inertia of the KKT
// matrix: that holds exactly when the Schur complement C K⁻¹ Cᵀ has as many negative
// eigenvalues as K has (Gould 1985; Nocedal & Wright, Thm 16.3), which K's pivots count.
// The tiles' Hessians need it: a yarn in tension may lower its energy by sliding along itself
// with the whole tile moving against it, a direction only the constraints forbid.
// `y`, when given, receives K⁻¹Cᵀ (the constrained step needs it too).
bool positive_definite_on_constraints(const ShiftedLdlt& k, const Eigen::MatrixXd& c, Eigen::MatrixXd* y = nullptr);

// The same for many solves with one factorisation: Y = K⁻¹Cᵀ and the Schur complement C Y are
// computed once.
class ConstrainedSolver {
 public:
  ConstrainedSolver(const ShiftedLdlt& k, const Eigen::MatrixXd& c);
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const;

 private:
  const ShiftedLdlt& m_k;
  const Eigen::MatrixXd& m_c;
  Eigen::MatrixXd m_y;
  Eigen::LDLT<Eigen::MatrixXd> m_schur, m_cct;
};

}  // namespace yarnfit::numerics
