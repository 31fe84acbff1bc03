#include "shell_fit/solver/newton.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace yarnfit::shell {

namespace {

using Clock = std::chrono::steady_clock;
using SparseMatrix = Eigen::SparseMatrix<double>;  // column-major
using Factorisation = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

void check_terms(const std::vector<const EnergyTerm*>& terms, const char* who) {
  if (terms.empty()) throw std::invalid_argument(std::string(who) + ": no energy terms");
  for (std::size_t i = 0; i < terms.size(); ++i) {
    if (terms[i] == nullptr) {
      throw std::invalid_argument(std::string(who) + ": energy term " + std::to_string(i) +
                                  " is null");
    }
  }
}

// Names of the terms whose value at x is not finite, e.g. "'membrane' = inf".
std::string describe_bad_values(const std::vector<const EnergyTerm*>& terms,
                                const Eigen::VectorXd& x) {
  std::string out;
  for (const EnergyTerm* term : terms) {
    const double v = term->value(x);
    if (std::isfinite(v)) continue;
    if (!out.empty()) out += ", ";
    out += "'" + term->name() + "' = " + (std::isnan(v) ? "NaN" : "inf");
  }
  return out.empty() ? "no single term (the sum overflowed)" : out;
}

// Names of the terms whose gradient at x has a non-finite entry.
std::string describe_bad_gradients(const std::vector<const EnergyTerm*>& terms,
                                   const Eigen::VectorXd& x) {
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

// Which DOFs are free, and their index among the free ones.
struct FreeDofs {
  std::vector<int> index_of;  // per DOF: free index, or −1 if fixed
  std::vector<int> dofs;      // per free index: the DOF

  FreeDofs(Eigen::Index n, const std::vector<int>& fixed) : index_of(static_cast<std::size_t>(n), 0) {
    for (const int d : fixed) {
      if (d < 0 || d >= n) {
        throw std::invalid_argument("solve_static: fixed DOF " + std::to_string(d) +
                                    " is out of range (x has " + std::to_string(n) + " entries)");
      }
      index_of[static_cast<std::size_t>(d)] = -1;
    }
    for (Eigen::Index d = 0; d < n; ++d) {
      auto& slot = index_of[static_cast<std::size_t>(d)];
      if (slot < 0) continue;
      slot = static_cast<int>(dofs.size());
      dofs.push_back(static_cast<int>(d));
    }
  }
  [[nodiscard]] int count() const { return static_cast<int>(dofs.size()); }

  [[nodiscard]] Eigen::VectorXd restrict(const Eigen::VectorXd& full) const {
    Eigen::VectorXd r(count());
    for (int i = 0; i < count(); ++i) r(i) = full(dofs[static_cast<std::size_t>(i)]);
    return r;
  }
  // full + alpha · (free step scattered), fixed DOFs untouched.
  void add_step(const Eigen::VectorXd& base, double alpha, const Eigen::VectorXd& step,
                Eigen::VectorXd& out) const {
    out = base;
    for (int i = 0; i < count(); ++i) out(dofs[static_cast<std::size_t>(i)]) += alpha * step(i);
  }
};

// Assembles the lower triangle of the free Hessian with an explicit diagonal (so the pattern
// holds the shift μI) and keeps the symbolic analysis while the pattern stays the same.
class FreeHessian {
 public:
  explicit FreeHessian(const FreeDofs& dofs) : m_free(dofs) {}

  // Returns false (with the names of the offending terms in *why) if an entry is not finite.
  bool assemble(const std::vector<const EnergyTerm*>& terms, const Eigen::VectorXd& x,
                bool project_psd, std::string* why) {
    const Eigen::Index n = x.size();
    m_triplets.clear();
    std::string bad;
    for (const EnergyTerm* term : terms) {
      const std::size_t begin = m_triplets.size();
      term->add_hessian(x, m_triplets, project_psd);
      bool finite = true;
      for (std::size_t k = begin; k < m_triplets.size(); ++k) {
        const auto& t = m_triplets[k];
        if (t.row() < 0 || t.row() >= n || t.col() < 0 || t.col() >= n) {
          throw std::logic_error("energy term '" + term->name() + "' wrote a Hessian entry (" +
                                 std::to_string(t.row()) + ", " + std::to_string(t.col()) +
                                 ") outside the " + std::to_string(n) + " DOFs");
        }
        finite = finite && std::isfinite(t.value());
      }
      if (!finite) bad += (bad.empty() ? "'" : ", '") + term->name() + "'";
    }
    if (!bad.empty()) {
      *why = "non-finite Hessian entries from " + bad;
      return false;
    }
    // Keep the free lower-triangle entries, renumbered, in place.
    std::size_t kept = 0;
    for (const auto& t : m_triplets) {
      const int r = m_free.index_of[static_cast<std::size_t>(t.row())];
      const int c = m_free.index_of[static_cast<std::size_t>(t.col())];
      if (r < 0 || c < 0 || r < c) continue;
      m_triplets[kept++] = Eigen::Triplet<double>(r, c, t.value());
    }
    m_triplets.resize(kept);
    for (int i = 0; i < m_free.count(); ++i) m_triplets.emplace_back(i, i, 0.0);
    m_matrix.resize(m_free.count(), m_free.count());
    m_matrix.setFromTriplets(m_triplets.begin(), m_triplets.end());
    m_base.assign(m_matrix.valuePtr(), m_matrix.valuePtr() + m_matrix.nonZeros());

    // Sorted column-major lower triangle: each column's diagonal is its first entry.
    m_scale = 0.0;
    for (int j = 0; j < m_free.count(); ++j) {
      m_scale += std::abs(m_matrix.valuePtr()[m_matrix.outerIndexPtr()[j]]);
    }
    m_scale = m_free.count() > 0 ? m_scale / m_free.count() : 1.0;
    if (!(m_scale > 0.0)) m_scale = 1.0;  // an all-zero diagonal: shifts relative to 1

    if (!m_analysed || !same_pattern()) {
      m_factorisation.analyzePattern(m_matrix);
      m_outer.assign(m_matrix.outerIndexPtr(), m_matrix.outerIndexPtr() + m_matrix.cols() + 1);
      m_inner.assign(m_matrix.innerIndexPtr(), m_matrix.innerIndexPtr() + m_matrix.nonZeros());
      m_analysed = true;
      ++m_analyses;
    }
    return true;
  }

  // Factorises H + shift·scale·I; false if that is not positive definite.
  bool factorise(double relative_shift) {
    double* values = m_matrix.valuePtr();
    std::copy(m_base.begin(), m_base.end(), values);
    const double shift = relative_shift * m_scale;
    for (int j = 0; j < m_free.count(); ++j) values[m_matrix.outerIndexPtr()[j]] += shift;
    m_factorisation.factorize(m_matrix);
    if (m_factorisation.info() != Eigen::Success) return false;
    // A positive D makes LDLᵀ positive definite, so the solve gives a descent direction.
    return m_free.count() == 0 || m_factorisation.vectorD().minCoeff() > 0.0;
  }

  // Smallest diagonal entry relative to the mean |diagonal|; a matrix with a non-positive
  // diagonal entry cannot be positive definite, so the shift must exceed −this.
  [[nodiscard]] double relative_min_diagonal() const {
    double lowest = std::numeric_limits<double>::infinity();
    for (int j = 0; j < m_free.count(); ++j) {
      lowest = std::min(lowest, m_base[static_cast<std::size_t>(m_matrix.outerIndexPtr()[j])]);
    }
    return lowest / m_scale;
  }

  [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    return m_factorisation.solve(rhs);
  }
  [[nodiscard]] int analyses() const { return m_analyses; }

 private:
  [[nodiscard]] bool same_pattern() const {
    return m_outer.size() == static_cast<std::size_t>(m_matrix.cols() + 1) &&
           m_inner.size() == static_cast<std::size_t>(m_matrix.nonZeros()) &&
           std::equal(m_outer.begin(), m_outer.end(), m_matrix.outerIndexPtr()) &&
           std::equal(m_inner.begin(), m_inner.end(), m_matrix.innerIndexPtr());
  }

  const FreeDofs& m_free;
  Triplets m_triplets;
  SparseMatrix m_matrix;
  std::vector<double> m_base;  // unshifted values of m_matrix
  double m_scale = 1.0;        // mean |diagonal|: the unit of the shift
  Factorisation m_factorisation;
  bool m_analysed = false;
  int m_analyses = 0;
  std::vector<int> m_outer, m_inner;  // the analysed pattern
};

}  // namespace

// ---------------------------------------------------------------------------------------------

bool NewtonOptions::is_valid(std::string* why) const {
  const auto fail = [&](const std::string& m) {
    if (why != nullptr) *why = "NewtonOptions." + m;
    return false;
  };
  if (max_iterations < 0) return fail("max_iterations must be ≥ 0");
  if (!(gradient_tolerance >= 0.0) || !std::isfinite(gradient_tolerance)) {
    return fail("gradient_tolerance must be finite and ≥ 0");
  }
  if (max_line_search_steps < 1) return fail("max_line_search_steps must be ≥ 1");
  if (!(armijo > 0.0 && armijo < 0.5)) return fail("armijo must be in (0, 0.5)");
  if (!(regularisation_start > 0.0) || !std::isfinite(regularisation_start)) {
    return fail("regularisation_start must be positive and finite");
  }
  if (!(regularisation_growth > 1.0) || !std::isfinite(regularisation_growth)) {
    return fail("regularisation_growth must be > 1 and finite");
  }
  if (!(regularisation_shrink > 0.0 && regularisation_shrink < 1.0)) {
    return fail("regularisation_shrink must be in (0, 1)");
  }
  if (!(regularisation_max >= regularisation_start) || !std::isfinite(regularisation_max)) {
    return fail("regularisation_max must be finite and ≥ regularisation_start");
  }
  return true;
}

bool ContinuationOptions::is_valid(std::string* why) const {
  std::string inner;
  if (!newton.is_valid(&inner)) {
    if (why != nullptr) *why = "ContinuationOptions.newton: " + inner;
    return false;
  }
  const auto fail = [&](const std::string& m) {
    if (why != nullptr) *why = "ContinuationOptions." + m;
    return false;
  };
  if (!std::isfinite(start_lambda) || start_lambda > 1.0) {
    return fail("start_lambda must be finite and ≤ 1");
  }
  if (!(min_step > 0.0) || !std::isfinite(min_step)) return fail("min_step must be positive");
  if (!(initial_step >= min_step) || !std::isfinite(initial_step)) {
    return fail("initial_step must be finite and ≥ min_step");
  }
  if (!(max_step >= initial_step) || !std::isfinite(max_step)) {
    return fail("max_step must be finite and ≥ initial_step");
  }
  if (!(step_growth >= 1.0) || !std::isfinite(step_growth)) return fail("step_growth must be ≥ 1");
  if (easy_iterations < 0) return fail("easy_iterations must be ≥ 0");
  return true;
}

const char* to_string(NewtonStatus status) {
  switch (status) {
    case NewtonStatus::converged: return "converged";
    case NewtonStatus::max_iterations: return "max_iterations";
    case NewtonStatus::line_search_failed: return "line_search_failed";
    case NewtonStatus::invalid_start: return "invalid_start";
    case NewtonStatus::linear_solver_failed: return "linear_solver_failed";
    case NewtonStatus::non_finite: return "non_finite";
  }
  return "unknown";
}

std::string NewtonSummary::brief() const {
  std::ostringstream out;
  out << "Newton " << to_string(status) << ": " << iterations << " iterations, |g|inf "
      << format_number(gradient_norm) << ", E " << format_number(energy) << ", "
      << format_number(seconds * 1e3) << " ms";
  if (projected_steps > 0) out << ", " << projected_steps << " projected";
  if (regularised_steps > 0) out << ", " << regularised_steps << " regularised";
  if (continuation_steps > 0 || cut_backs > 0) {
    out << ", " << continuation_steps << " load steps, " << cut_backs << " cut-backs, lambda "
        << format_number(lambda);
  }
  if (!converged() && !message.empty()) out << " (" << message << ")";
  return out.str();
}

double total_energy(const std::vector<const EnergyTerm*>& terms, const Eigen::VectorXd& x) {
  double e = 0.0;
  for (const EnergyTerm* term : terms) {
    const double v = term->value(x);
    if (std::isnan(v)) return v;  // a contract breach: report it, do not let +inf mask it
    e += v;
  }
  return e;
}

Eigen::VectorXd total_gradient(const std::vector<const EnergyTerm*>& terms,
                               const Eigen::VectorXd& x) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  for (const EnergyTerm* term : terms) term->add_gradient(x, g);
  return g;
}

SparseMatrix total_hessian(const std::vector<const EnergyTerm*>& terms, const Eigen::VectorXd& x,
                           bool project_psd) {
  Triplets triplets;
  for (const EnergyTerm* term : terms) term->add_hessian(x, triplets, project_psd);
  SparseMatrix h(x.size(), x.size());
  h.setFromTriplets(triplets.begin(), triplets.end());
  return h;
}

Eigen::VectorXd clamp_reaction(const std::vector<const EnergyTerm*>& terms,
                               const Eigen::VectorXd& x, const std::vector<int>& dofs) {
  const Eigen::VectorXd g = total_gradient(terms, x);
  Eigen::VectorXd r(static_cast<Eigen::Index>(dofs.size()));
  for (std::size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i] < 0 || dofs[i] >= x.size()) {
      throw std::invalid_argument("clamp_reaction: DOF " + std::to_string(dofs[i]) +
                                  " is out of range");
    }
    r(static_cast<Eigen::Index>(i)) = g(dofs[i]);
  }
  return r;
}

double clamp_force(const std::vector<const EnergyTerm*>& terms, const Eigen::VectorXd& x,
                   const std::vector<int>& vertices, int dim, int axis) {
  if (dim < 1 || axis < 0 || axis >= dim) {
    throw std::invalid_argument("clamp_force: axis " + std::to_string(axis) +
                                " is not below dim " + std::to_string(dim));
  }
  std::vector<int> dofs;
  dofs.reserve(vertices.size());
  for (const int v : vertices) dofs.push_back(dim * v + axis);
  return clamp_reaction(terms, x, dofs).sum();
}

std::vector<int> vertex_dofs(const std::vector<int>& vertices, int dim) {
  std::vector<int> dofs;
  dofs.reserve(vertices.size() * static_cast<std::size_t>(dim));
  for (const int v : vertices) {
    for (int k = 0; k < dim; ++k) dofs.push_back(dim * v + k);
  }
  return dofs;
}

// ---------------------------------------------------------------------------------------------

NewtonSummary solve_static(const std::vector<const EnergyTerm*>& terms, Eigen::VectorXd& x,
                           const std::vector<int>& fixed_dofs, const NewtonOptions& options) {
  const auto start = Clock::now();
  std::string why;
  if (!options.is_valid(&why)) throw std::invalid_argument("solve_static: " + why);
  check_terms(terms, "solve_static");
  const FreeDofs free_dofs(x.size(), fixed_dofs);

  NewtonSummary summary;
  const auto finish = [&](NewtonStatus status, std::string message) {
    summary.status = status;
    summary.message = std::move(message);
    summary.seconds = seconds_since(start);
    return summary;
  };

  double energy = total_energy(terms, x);
  summary.energy = energy;
  if (!std::isfinite(energy)) {
    summary.gradient_norm = std::numeric_limits<double>::quiet_NaN();
    return finish(NewtonStatus::invalid_start,
                  "initial energy is not finite: " + describe_bad_values(terms, x));
  }

  FreeHessian hessian(free_dofs);
  Eigen::VectorXd gradient = total_gradient(terms, x);
  Eigen::VectorXd trial(x.size());
  double shift = 0.0;              // relative Levenberg shift μ; 0 = plain Newton
  bool exact_failed_last = false;  // the exact Hessian was not usable last iteration
  int nan_trials = 0;              // trial energies that were NaN (a term breaking its contract)

  while (true) {
    if (!gradient.allFinite()) {
      return finish(NewtonStatus::non_finite, "gradient is not finite at a state of finite energy "
                                              "(from " + describe_bad_gradients(terms, x) + ")");
    }
    const Eigen::VectorXd g_free = free_dofs.restrict(gradient);
    const double g_norm = free_dofs.count() > 0 ? g_free.lpNorm<Eigen::Infinity>() : 0.0;
    summary.gradient_norm = g_norm;
    summary.energy = energy;
    if (g_norm <= options.gradient_tolerance) {
      return finish(NewtonStatus::converged, "|g|inf " + format_number(g_norm) + " <= tolerance " +
                                                 format_number(options.gradient_tolerance));
    }
    if (summary.iterations >= options.max_iterations) {
      return finish(NewtonStatus::max_iterations,
                    "stopped after " + std::to_string(summary.iterations) + " iterations with |g|inf " +
                        format_number(g_norm) + " > tolerance " +
                        format_number(options.gradient_tolerance));
    }

    // The exact Hessian first (cheap, and the true Newton step) unless it failed last time;
    // the per-element projection when the exact one is indefinite.
    bool exact = !options.project_psd || (options.exact_hessian_first && !exact_failed_last);
    // Projection chosen up front because the exact Hessian failed last iteration: that lasts
    // one iteration, after which the exact Hessian is tried again.
    const bool skipped_exact = options.project_psd && options.exact_hessian_first && exact_failed_last;
    const auto assemble = [&]() {
      if (!hessian.assemble(terms, x, !exact, &why)) return false;
      // A non-positive diagonal entry rules out positive definiteness: start the shift past it.
      const double lowest = hessian.relative_min_diagonal();
      if (lowest <= 0.0) shift = std::max(shift, options.regularisation_start - lowest);
      return true;
    };
    if (!assemble()) return finish(NewtonStatus::non_finite, why);

    // Find a Hessian and shift whose direction descends and admits an Armijo step. Each failure
    // first swaps the exact Hessian for the projected one, then grows the shift, which turns
    // the direction towards steepest descent and shortens it.
    bool accepted = false;
    bool factorised_once = false;
    bool gradient_cached = false;
    std::string last_failure;
    while (!accepted) {
      bool at_rounding_floor = false;
      if (hessian.factorise(shift)) {
        factorised_once = true;
        const Eigen::VectorXd step = hessian.solve(-g_free);
        const double slope = g_free.dot(step);
        if (!step.allFinite()) {
          last_failure = "the Newton step was not finite";
        } else if (!(slope < 0.0)) {
          last_failure = "the Newton step was not a descent direction";
        } else {
          double alpha = 1.0;
          int infinite_trials = 0;
          for (int k = 0; k < options.max_line_search_steps; ++k, alpha *= 0.5) {
            free_dofs.add_step(x, alpha, step, trial);
            const double e_trial = total_energy(terms, trial);
            if (std::isnan(e_trial)) ++nan_trials;
            if (!std::isfinite(e_trial)) {
              ++infinite_trials;
              continue;  // outside a term's domain: never step there
            }
            if (e_trial <= energy + options.armijo * alpha * slope) {
              accepted = true;
              energy = e_trial;
              break;
            }
            // Near the solution the decrease ½gᵀH⁻¹g drowns in the rounding of E; the full
            // Newton step is then still accepted if it halves the gradient.
            if (k == 0 && std::abs(e_trial - energy) <= 1e-12 * std::abs(energy)) {
              Eigen::VectorXd g_trial = total_gradient(terms, trial);
              if (g_trial.allFinite() &&
                  free_dofs.restrict(g_trial).lpNorm<Eigen::Infinity>() <= 0.5 * g_norm) {
                accepted = true;
                energy = e_trial;
                gradient = std::move(g_trial);
                gradient_cached = true;
                break;
              }
            }
          }
          if (!accepted) {
            last_failure = "no Armijo step in " + std::to_string(options.max_line_search_steps) +
                           " halvings (" + std::to_string(infinite_trials) +
                           " trial points had non-finite energy)";
            // The predicted decrease is below the rounding of E: larger shifts only shrink it.
            at_rounding_floor = -slope <= 1e-12 * std::abs(energy);
          }
        }
      } else {
        last_failure = "the shifted Hessian was not positive definite";
      }
      if (accepted) break;

      if (exact && options.project_psd) {
        exact = false;
        exact_failed_last = true;
        if (!assemble()) return finish(NewtonStatus::non_finite, why);
        continue;
      }
      if (at_rounding_floor) {
        return finish(NewtonStatus::line_search_failed,
                      "the energy cannot decrease further within rounding (|g|inf " +
                          format_number(g_norm) + " > tolerance " +
                          format_number(options.gradient_tolerance) +
                          "): the tolerance is below what this problem can resolve");
      }
      shift = shift == 0.0 ? options.regularisation_start : shift * options.regularisation_growth;
      if (shift > options.regularisation_max) {
        std::string message = last_failure + " at every shift up to " +
                              format_number(options.regularisation_max) +
                              " x mean |diag H|; |g|inf " + format_number(g_norm);
        if (nan_trials > 0) {
          message += "; " + std::to_string(nan_trials) +
                     " trial energies were NaN (a term breaks its contract)";
        }
        return finish(factorised_once ? NewtonStatus::line_search_failed
                                      : NewtonStatus::linear_solver_failed,
                      message);
      }
    }
    if (exact || skipped_exact) exact_failed_last = false;

    x.swap(trial);  // the accepted trial point
    ++summary.iterations;
    if (shift > 0.0) ++summary.regularised_steps;
    if (!exact) ++summary.projected_steps;
    shift *= options.regularisation_shrink;
    if (shift < options.regularisation_start) shift = 0.0;
    if (!gradient_cached) gradient = total_gradient(terms, x);
  }
}


// ---------------------------------------------------------------------------------------------

NewtonSummary solve_continuation(const std::vector<const EnergyTerm*>& terms, Eigen::VectorXd& x,
                                 const std::vector<int>& fixed_dofs,
                                 const SetBoundary& set_boundary,
                                 const ContinuationOptions& options) {
  const auto start = Clock::now();
  std::string why;
  if (!options.is_valid(&why)) throw std::invalid_argument("solve_continuation: " + why);
  if (!set_boundary) throw std::invalid_argument("solve_continuation: set_boundary is empty");
  check_terms(terms, "solve_continuation");
  const FreeDofs free_dofs(x.size(), fixed_dofs);

  NewtonSummary total;
  total.lambda = options.start_lambda;
  const auto add_solve = [&](const NewtonSummary& s) {
    total.iterations += s.iterations;
    total.regularised_steps += s.regularised_steps;
    total.projected_steps += s.projected_steps;
  };
  const auto finish = [&](const NewtonSummary& last, std::string message) {
    total.status = last.status;
    total.message = std::move(message);
    total.seconds = seconds_since(start);
    return total;
  };

  // Equilibrium at the start load, so every later warm start comes from a solution.
  Eigen::VectorXd current = x;
  set_boundary(options.start_lambda, current);
  const NewtonSummary first = solve_static(terms, current, fixed_dofs, options.newton);
  add_solve(first);
  total.energy = first.energy;
  total.gradient_norm = first.gradient_norm;
  if (!first.converged()) {
    return finish(first, "continuation: no equilibrium at the start, lambda = " +
                             format_number(options.start_lambda) + ": " + first.message);
  }
  x = current;

  double lambda = options.start_lambda;
  double step = options.initial_step;
  Eigen::VectorXd previous;  // the solution before `current`, for extrapolation
  double previous_lambda = 0.0;
  bool have_previous = false;
  Eigen::VectorXd candidate(x.size());

  while (lambda < 1.0) {
    double target = std::min(1.0, lambda + step);
    if (1.0 - target < 1e-12) target = 1.0;

    candidate = current;
    bool extrapolated = false;
    if (options.extrapolate && have_previous) {
      const double ratio = (target - lambda) / (lambda - previous_lambda);
      for (const int d : free_dofs.dofs) candidate(d) += ratio * (current(d) - previous(d));
      extrapolated = true;
    }
    set_boundary(target, candidate);
    if (extrapolated && !std::isfinite(total_energy(terms, candidate))) {
      // The prediction overshot into an invalid state: start from the last solution instead.
      candidate = current;
      set_boundary(target, candidate);
    }

    const NewtonSummary s = solve_static(terms, candidate, fixed_dofs, options.newton);
    add_solve(s);
    if (s.converged()) {
      previous.swap(current);
      current.swap(candidate);
      previous_lambda = lambda;
      have_previous = true;
      lambda = target;
      x = current;
      ++total.continuation_steps;
      total.lambda = lambda;
      total.energy = s.energy;
      total.gradient_norm = s.gradient_norm;
      if (s.iterations <= options.easy_iterations) {
        step = std::min(options.max_step, step * options.step_growth);
      }
      continue;
    }

    ++total.cut_backs;
    step *= 0.5;
    if (step < options.min_step) {
      x = current;  // the last converged state
      return finish(s, "continuation stopped at lambda = " + format_number(lambda) +
                           ": the load step to " + format_number(target) + " failed (" +
                           to_string(s.status) + ": " + s.message + ") and the halved step " +
                           format_number(step) + " fell below min_step " +
                           format_number(options.min_step) + " after " +
                           std::to_string(total.cut_backs) + " cut-backs");
    }
  }

  NewtonSummary done;
  done.status = NewtonStatus::converged;
  return finish(done, "continuation reached lambda = 1 in " +
                          std::to_string(total.continuation_steps) + " load steps (" +
                          std::to_string(total.cut_backs) + " cut-backs), " +
                          std::to_string(total.iterations) + " Newton iterations");
}

}  // namespace yarnfit::shell
