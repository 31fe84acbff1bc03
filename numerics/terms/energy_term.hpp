#pragma once
// One energy term of a scene, for both simulators (SPEC §4; STYLE "Energies as composable
// pieces", after PolyFEM's forms and IPC Toolkit's potentials). A scene is a list of terms;
// the solver sums them. Every term has value, gradient and Hessian (each checked by finite
// differences in its own test), an optional per-element PSD projection of the Hessian, and
// the two hooks a line search calls: the largest safe step along a direction (a contact
// barrier's collision-free step) and the validity of a step.
//
// `x` holds all degrees of freedom flat (a simulator decides what they are: shell vertex
// positions, yarn fluctuations). Values, gradients and Hessians are *added* into the caller's
// accumulators, so terms compose without temporaries and a scene can sum many terms in one
// running total.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cmath>
#include <string>
#include <vector>

namespace yarnfit::numerics {

using Triplets = std::vector<Eigen::Triplet<double>>;

struct HessianOptions {
  // Project every element's block onto the PSD cone (Newton's safeguard far from rest, where
  // compressed membranes, dihedral angles, rod corners and barriers are indefinite).
  bool project_psd = false;
  // Only entries with row ≥ column (what a lower-triangular LDLᵀ reads).
  bool lower_only = false;
};

class EnergyTerm {
 public:
  virtual ~EnergyTerm() = default;
  EnergyTerm() = default;
  EnergyTerm(const EnergyTerm&) = delete;
  EnergyTerm& operator=(const EnergyTerm&) = delete;

  // The term's name, recorded in every result as an effect the scene simulated.
  [[nodiscard]] virtual std::string name() const = 0;

  // Adds the energy [J] to `energy`: +infinity where x is outside the term's domain (an
  // inverted triangle, crossed barrier); never NaN for a valid term.
  virtual void add_value(const Eigen::VectorXd& x, double& energy) const = 0;
  virtual void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& gradient) const = 0;
  // Appends Hessian entries as triplets (duplicates are summed by the caller).
  virtual void add_hessian(const Eigen::VectorXd& x, Triplets& hessian,
                           const HessianOptions& options) const = 0;
  // Value and gradient in one pass where a term computes both together (the default calls
  // the two above).
  virtual void add_value_gradient(const Eigen::VectorXd& x, double& energy,
                                  Eigen::VectorXd& gradient) const {
    add_value(x, energy);
    add_gradient(x, gradient);
  }

  // Line-search hooks. The largest t ∈ (0, 1] such that x + t·dx is safe to evaluate (for a
  // barrier: no element closes by more than half its distance, so a step never crosses it).
  [[nodiscard]] virtual double max_step(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*dx*/) const {
    return 1.0;
  }
  // Whether moving from x to `trial` is acceptable beyond a finite energy (default: yes).
  [[nodiscard]] virtual bool is_step_valid(const Eigen::VectorXd& /*x*/, const Eigen::VectorXd& /*trial*/) const {
    return true;
  }

  [[nodiscard]] double value(const Eigen::VectorXd& x) const {
    double e = 0.0;
    add_value(x, e);
    return e;
  }
  // True where value(x) is finite.
  [[nodiscard]] bool is_valid(const Eigen::VectorXd& x) const { return std::isfinite(value(x)); }
};

}  // namespace yarnfit::numerics
