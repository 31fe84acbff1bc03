#pragma once
// A scene's energy as a list of terms (SPEC §4: a scene simulates exactly the effects it
// lists). The totals add every term into one accumulator in list order; the names of the
// terms are the effects a result records.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "numerics/terms/energy_term.hpp"

namespace yarnfit::numerics {

using TermList = std::vector<const EnergyTerm*>;

// Throws an input Error (naming `who`) for an empty list or a null term.
void check_terms(const TermList& terms, const char* who);

// Names of the terms, in order: the effects a scene simulated.
[[nodiscard]] std::vector<std::string> term_names(const TermList& terms);
// Adds to `effects` the names in `more` it does not hold yet, in their order (the effects of a
// result made of several scenes).
void merge_effects(std::vector<std::string>& effects, const std::vector<std::string>& more);

// Sum of the terms at x: +inf if any term is infinite, NaN as soon as one is NaN (a broken
// contract that +inf must not hide).
[[nodiscard]] double total_energy(const TermList& terms, const Eigen::VectorXd& x);
[[nodiscard]] Eigen::VectorXd total_gradient(const TermList& terms, const Eigen::VectorXd& x);
// The full Hessian (#x × #x, both triangles stored).
[[nodiscard]] Eigen::SparseMatrix<double> total_hessian(const TermList& terms, const Eigen::VectorXd& x,
                                                        bool project_psd);
// Smallest of the terms' safe step fractions along dx (1 when no term limits it).
[[nodiscard]] double max_step(const TermList& terms, const Eigen::VectorXd& x, const Eigen::VectorXd& dx);

// Diagnostics for solver messages: the terms whose value (gradient) at x is not finite,
// e.g. "'membrane' = inf", or "no single term (the sum overflowed)".
[[nodiscard]] std::string describe_non_finite_values(const TermList& terms, const Eigen::VectorXd& x);
[[nodiscard]] std::string describe_non_finite_gradients(const TermList& terms, const Eigen::VectorXd& x);

}  // namespace yarnfit::numerics
