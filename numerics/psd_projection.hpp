#pragma once
// Projection of a small symmetric element block onto the positive semi-definite cone:
// H = Q Λ Qᵀ  ->  Q max(Λ, 0) Qᵀ. Newton needs a PSD Hessian far from rest, where StVK
// under compression and the dihedral-angle Hessian are indefinite; projecting per element
// keeps the assembled matrix PSD while leaving convex elements untouched.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace yarnfit::numerics {

template <int N>
void project_psd(Eigen::Matrix<double, N, N>& h) {
  // Symmetrise first: round-off makes the analytic blocks asymmetric in the last digits.
  const Eigen::Matrix<double, N, N> sym = 0.5 * (h + h.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(sym);
  if (eig.info() != Eigen::Success) {
    h = sym;  // no decomposition: keep the block rather than invent one
    return;
  }
  const auto& values = eig.eigenvalues();
  if (values.minCoeff() >= 0.0) {
    h = sym;
    return;
  }
  const Eigen::Matrix<double, N, 1> clamped = values.cwiseMax(0.0);
  h = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace yarnfit::numerics
