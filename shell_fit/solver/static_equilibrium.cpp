#include "shell_fit/solver/static_equilibrium.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "numerics/util/format.hpp"

namespace yarnfit::shell {

namespace {

using numerics::Clock;

// Which DOFs are free, and their index among the free ones.
struct FreeDofs {
  std::vector<int> index_of;  // per DOF: free index, or −1 if fixed
  std::vector<int> dofs;      // per free index: the DOF

  FreeDofs(Eigen::Index n, const std::vector<int>& fixed) : index_of(static_cast<std::size_t>(n), 0) {
    for (const int d : fixed) {
      if (d < 0 || d >= n) {
        throw Error(ErrorCategory::input, "solve_static: fixed DOF " + std::to_string(d) +
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
  // Writes the free values into `full` (the fixed entries are left as they are).
  void scatter(const Eigen::VectorXd& free, Eigen::VectorXd& full) const {
    for (int i = 0; i < count(); ++i) full(dofs[static_cast<std::size_t>(i)]) = free(i);
  }
};

// A shell scene's terms as a Newton problem over the free DOFs: the clamped DOFs keep the
// values of the state the solve started from.
class FreeDofProblem final : public numerics::NewtonProblem {
 public:
  FreeDofProblem(const TermList& terms, const Eigen::VectorXd& start, const FreeDofs& free)
      : m_terms(terms), m_free(free), m_full(start) {}

  [[nodiscard]] int size() const override { return m_free.count(); }
  [[nodiscard]] double energy(const Eigen::VectorXd& x) const override { return total_energy(m_terms, full(x)); }
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& gradient) const override {
    const Eigen::VectorXd& state = full(x);
    const double e = total_energy(m_terms, state);
    if (!std::isfinite(e)) {
      // Outside a term's domain derivatives are not defined: never ask for them there.
      gradient.setConstant(m_free.count(), std::numeric_limits<double>::quiet_NaN());
      return e;
    }
    const Eigen::VectorXd g = total_gradient(m_terms, state);
    gradient = m_free.restrict(g);
    // A non-finite entry anywhere (a clamped DOF too) means a term broke its contract.
    if (!g.allFinite()) gradient.setConstant(std::numeric_limits<double>::quiet_NaN());
    return e;
  }
  bool hessian(const Eigen::VectorXd& x, bool project_psd, Triplets& lower, std::string* why) const override {
    const Eigen::VectorXd& state = full(x);
    const Eigen::Index n = state.size();
    std::string bad;
    for (const EnergyTerm* term : m_terms) {
      m_scratch.clear();
      term->add_hessian(state, m_scratch, {project_psd, /*lower_only=*/true});
      bool finite = true;
      for (const auto& t : m_scratch) {
        if (t.row() < 0 || t.row() >= n || t.col() < 0 || t.col() >= n) {
          throw std::logic_error("energy term '" + term->name() + "' wrote a Hessian entry (" +
                                 std::to_string(t.row()) + ", " + std::to_string(t.col()) + ") outside the " +
                                 std::to_string(n) + " DOFs");
        }
        finite = finite && std::isfinite(t.value());
        // The free lower triangle, renumbered (a term may write both triangles).
        const int r = m_free.index_of[static_cast<std::size_t>(t.row())];
        const int c = m_free.index_of[static_cast<std::size_t>(t.col())];
        if (r >= 0 && c >= 0 && r >= c) lower.emplace_back(r, c, t.value());
      }
      if (!finite) bad += (bad.empty() ? "'" : ", '") + term->name() + "'";
    }
    if (bad.empty()) return true;
    *why = "non-finite Hessian entries from " + bad;
    return false;
  }
  [[nodiscard]] std::string describe_invalid_energy(const Eigen::VectorXd& x) const override {
    return numerics::describe_non_finite_values(m_terms, full(x));
  }
  [[nodiscard]] std::string describe_invalid_gradient(const Eigen::VectorXd& x) const override {
    return numerics::describe_non_finite_gradients(m_terms, full(x));
  }

 private:
  const Eigen::VectorXd& full(const Eigen::VectorXd& free) const {
    m_free.scatter(free, m_full);
    return m_full;
  }
  const TermList& m_terms;
  const FreeDofs& m_free;
  mutable Eigen::VectorXd m_full;
  mutable Triplets m_scratch;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

numerics::Problems ContinuationOptions::problems() const {
  numerics::Problems out;
  newton.add_problems(out, "ContinuationOptions.newton.");
  const auto bad = [&](const char* field, const char* m) { out.add_field(std::string("ContinuationOptions.") + field, m); };
  if (!std::isfinite(start_lambda) || start_lambda > 1.0) bad("start_lambda", "must be finite and ≤ 1");
  if (!(min_step > 0.0) || !std::isfinite(min_step)) bad("min_step", "must be positive");
  if (!(initial_step >= min_step) || !std::isfinite(initial_step)) bad("initial_step", "must be finite and ≥ min_step");
  if (!(max_step >= initial_step) || !std::isfinite(max_step)) bad("max_step", "must be finite and ≥ initial_step");
  if (!(step_growth >= 1.0) || !std::isfinite(step_growth)) bad("step_growth", "must be ≥ 1");
  if (easy_iterations < 0) bad("easy_iterations", "must be ≥ 0");
  return out;
}

Eigen::VectorXd clamp_reaction(const TermList& terms, const Eigen::VectorXd& x, const std::vector<int>& dofs) {
  const Eigen::VectorXd g = total_gradient(terms, x);
  Eigen::VectorXd r(static_cast<Eigen::Index>(dofs.size()));
  for (std::size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i] < 0 || dofs[i] >= x.size()) {
      throw Error(ErrorCategory::input, "clamp_reaction: DOF " + std::to_string(dofs[i]) + " is out of range");
    }
    r(static_cast<Eigen::Index>(i)) = g(dofs[i]);
  }
  return r;
}

double clamp_force(const TermList& terms, const Eigen::VectorXd& x, const std::vector<int>& vertices, int dim,
                   int axis) {
  if (dim < 1 || axis < 0 || axis >= dim) {
    throw Error(ErrorCategory::input, "clamp_force: axis " + std::to_string(axis) + " is not below dim " +
                                std::to_string(dim));
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

std::vector<int> free_dof_index(int dof_count, const std::vector<int>& fixed_dofs, int& free_count) {
  std::vector<int> index(static_cast<std::size_t>(dof_count), 0);
  for (int d : fixed_dofs) index[static_cast<std::size_t>(d)] = -1;
  free_count = 0;
  for (int& f : index)
    if (f == 0) f = free_count++;
  return index;
}

Eigen::SparseMatrix<double> free_block(const Eigen::SparseMatrix<double>& h, const std::vector<int>& free_index,
                                       int free_count) {
  std::vector<Eigen::Triplet<double>> ff;
  for (int k = 0; k < h.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(h, k); it; ++it) {
      const int fr = free_index[static_cast<std::size_t>(it.row())];
      const int fc = free_index[static_cast<std::size_t>(it.col())];
      if (fr >= 0 && fc >= 0) ff.emplace_back(fr, fc, it.value());
    }
  }
  Eigen::SparseMatrix<double> hff(free_count, free_count);
  hff.setFromTriplets(ff.begin(), ff.end());
  return hff;
}

NewtonSummary solve_static(const TermList& terms, Eigen::VectorXd& x, const std::vector<int>& fixed_dofs,
                           const NewtonOptions& options) {
  if (const numerics::Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "solve_static: " + problems.one_line());
  numerics::check_terms(terms, "solve_static");
  const FreeDofs free_dofs(x.size(), fixed_dofs);
  FreeDofProblem problem(terms, x, free_dofs);
  Eigen::VectorXd free = free_dofs.restrict(x);
  const NewtonSummary summary = numerics::solve_newton(problem, free, options);
  free_dofs.scatter(free, x);
  return summary;
}

// ---------------------------------------------------------------------------------------------

namespace {

// A solve's iteration and step counts, added to the continuation's.
void add_counts(NewtonSummary& total, const NewtonSummary& s) {
  total.iterations += s.iterations;
  total.regularised_steps += s.regularised_steps;
  total.projected_steps += s.projected_steps;
}

// The loads of a continuation step: the last two solved and the one to solve next.
struct LoadStep {
  double lambda;           // the last solution's
  double previous_lambda;  // the one before it
  double target;           // the next
};

// Where the solve at the target load starts: the last solution `current`, moved along the last
// load step (from `previous`) when `extrapolate`, with the boundary at the target. A prediction
// that overshoots into a state of infinite energy is dropped for the last solution.
void predict_start(const TermList& terms, const FreeDofs& free_dofs, const SetBoundary& set_boundary, bool extrapolate,
                   const LoadStep& step, const Eigen::VectorXd& current, const Eigen::VectorXd& previous,
                   Eigen::VectorXd& candidate) {
  candidate = current;
  if (extrapolate) {
    const double ratio = (step.target - step.lambda) / (step.lambda - step.previous_lambda);
    for (const int d : free_dofs.dofs) candidate(d) += ratio * (current(d) - previous(d));
  }
  set_boundary(step.target, candidate);
  if (extrapolate && !std::isfinite(total_energy(terms, candidate))) {
    candidate = current;
    set_boundary(step.target, candidate);
  }
}

std::string stopped_message(double lambda, double target, const NewtonSummary& failed, double step, double min_step,
                            int cut_backs) {
  return "continuation stopped at lambda = " + numerics::format_number(lambda) + ": the load step to " +
         numerics::format_number(target) + " failed (" + to_string(failed.status) + ": " + failed.message +
         ") and the halved step " + numerics::format_number(step) + " fell below min_step " +
         numerics::format_number(min_step) + " after " + std::to_string(cut_backs) + " cut-backs";
}

}  // namespace

NewtonSummary solve_continuation(const TermList& terms, Eigen::VectorXd& x, const std::vector<int>& fixed_dofs,
                                 const SetBoundary& set_boundary, const ContinuationOptions& options) {
  const auto start = Clock::now();
  if (const numerics::Problems problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "solve_continuation: " + problems.one_line());
  if (!set_boundary) throw Error(ErrorCategory::input, "solve_continuation: set_boundary is empty");
  numerics::check_terms(terms, "solve_continuation");
  const FreeDofs free_dofs(x.size(), fixed_dofs);

  NewtonSummary total;
  total.lambda = options.start_lambda;
  const auto finish = [&](const NewtonSummary& last, std::string message) {
    total.status = last.status;
    total.message = std::move(message);
    total.seconds = numerics::seconds_since(start);
    return total;
  };

  // Equilibrium at the start load, so every later warm start comes from a solution.
  Eigen::VectorXd current = x;
  set_boundary(options.start_lambda, current);
  const NewtonSummary first = solve_static(terms, current, fixed_dofs, options.newton);
  add_counts(total, first);
  total.energy = first.energy;
  total.residual = first.residual;
  if (!first.converged()) {
    return finish(first, "continuation: no equilibrium at the start, lambda = " +
                             numerics::format_number(options.start_lambda) + ": " + first.message);
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

    const LoadStep last{lambda, previous_lambda, target};
    predict_start(terms, free_dofs, set_boundary, options.extrapolate && have_previous, last, current, previous, candidate);

    const NewtonSummary s = solve_static(terms, candidate, fixed_dofs, options.newton);
    add_counts(total, s);
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
      total.residual = s.residual;
      if (s.iterations <= options.easy_iterations) {
        step = std::min(options.max_step, step * options.step_growth);
      }
      continue;
    }

    ++total.cut_backs;
    step *= 0.5;
    if (step < options.min_step) {
      x = current;  // the last converged state
      return finish(s, stopped_message(lambda, target, s, step, options.min_step, total.cut_backs));
    }
  }

  NewtonSummary done;
  done.status = NewtonStatus::converged;
  return finish(done, "continuation reached lambda = 1 in " + std::to_string(total.continuation_steps) +
                          " load steps (" + std::to_string(total.cut_backs) + " cut-backs), " +
                          std::to_string(total.iterations) + " Newton iterations");
}

}  // namespace yarnfit::shell
