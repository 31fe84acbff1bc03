#include "numerics/terms/scene.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace yarnfit::numerics {

void check_terms(const TermList& terms, const char* who) {
  if (terms.empty()) throw Error(ErrorCategory::input, std::string(who) + ": no energy terms");
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (terms[i] == nullptr)
      throw Error(ErrorCategory::input, std::string(who) + ": energy term " + std::to_string(i) + " is null");
  }
}

std::vector<std::string> term_names(const TermList& terms) {
  std::vector<std::string> names;
  names.reserve(terms.size());
  for (const EnergyTerm* t : terms) names.push_back(t->name());
  return names;
}

void merge_effects(std::vector<std::string>& effects, const std::vector<std::string>& more) {
  for (const std::string& name : more)
    if (std::find(effects.begin(), effects.end(), name) == effects.end()) effects.push_back(name);
}

double total_energy(const TermList& terms, const Eigen::VectorXd& x) {
  double e = 0.0;
  for (const EnergyTerm* term : terms) {
    term->add_value(x, e);
    if (std::isnan(e)) return e;
  }
  return e;
}

Eigen::VectorXd total_gradient(const TermList& terms, const Eigen::VectorXd& x) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  for (const EnergyTerm* term : terms) term->add_gradient(x, g);
  return g;
}

Eigen::SparseMatrix<double> total_hessian(const TermList& terms, const Eigen::VectorXd& x, bool project_psd) {
  Triplets triplets;
  for (const EnergyTerm* term : terms) term->add_hessian(x, triplets, {project_psd, false});
  Eigen::SparseMatrix<double> h(x.size(), x.size());
  h.setFromTriplets(triplets.begin(), triplets.end());
  return h;
}

double max_step(const TermList& terms, const Eigen::VectorXd& x, const Eigen::VectorXd& dx) {
  double t = 1.0;
  for (const EnergyTerm* term : terms) t = std::min(t, term->max_step(x, dx));
  return t;
}

std::string describe_non_finite_values(const TermList& terms, const Eigen::VectorXd& x) {
  std::string out;
  for (const EnergyTerm* term : terms) {
    const double v = term->value(x);
    if (std::isfinite(v)) continue;
    if (!out.empty()) out += ", ";
    out += "'" + term->name() + "' = " + (std::isnan(v) ? "NaN" : "inf");
  }
  return out.empty() ? "no single term (the sum overflowed)" : out;
}

std::string describe_non_finite_gradients(const TermList& terms, const Eigen::VectorXd& x) {
  std::string out;
  Eigen::VectorXd g(x.size());
  for (const EnergyTerm* term : terms) {
    g.setZero();
    term->add_gradient(x, g);
    if (g.allFinite()) continue;
    if (!out.empty()) out += ", ";
    out += "'" + term->name() + "'";
  }
  return out.empty() ? "no single term (the sum overflowed)" : out;
}

}  // namespace yarnfit::numerics
