#pragma once
// One energy term of a scene (SPEC §4, STYLE "Energies as composable pieces"). A scene is a
// list of terms; the solver sums them. Each term has value, gradient and Hessian, checked by
// finite differences in tests/shell_fit.
//
// `x` holds all vertex positions flat (dim per vertex). Gradients and Hessians are *added*
// into the caller's buffers, so terms compose without temporaries.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace yarnfit::shell {

using Triplets = std::vector<Eigen::Triplet<double>>;

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;
  EnergyTerm() = default;
  EnergyTerm(const EnergyTerm&) = delete;
  EnergyTerm& operator=(const EnergyTerm&) = delete;

  [[nodiscard]] virtual std::string name() const = 0;
  // Energy [J]; +infinity where the state is outside the term's domain (e.g. an inverted
  // triangle with a log barrier). Never NaN.
  [[nodiscard]] virtual double value(const Eigen::VectorXd& x) const = 0;
  virtual void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const = 0;
  // Adds the Hessian as triplets. With `project_psd`, every element's block is projected to
  // be positive semi-definite (eigenvalues clamped at 0), which Newton needs far from rest.
  virtual void add_hessian(const Eigen::VectorXd& x, Triplets& h, bool project_psd) const = 0;
  // True where value(x) is finite.
  [[nodiscard]] virtual bool is_valid(const Eigen::VectorXd& x) const { return std::isfinite(value(x)); }
};

}  // namespace yarnfit::shell
