#pragma once
// The one assembler of element energies (STYLE "Assemble in one place, in parallel"): an
// energy term made of many small elements (a triangle, an edge of four vertices, a yarn
// segment, a rod corner, a contact pair) describes one element; these functions sum the
// elements' values, scatter their local gradients and append their local Hessians.
//
// Parallel and reproducible. Above a size threshold, and when not already inside a parallel
// region (the swarm evaluates particles in parallel, the shell fit its directions), elements
// are evaluated by OpenMP threads into per-element slots, which are then reduced serially in
// element order. The result is therefore bitwise the same for any thread count, and the same
// as the serial loop (SPEC §5a: results do not depend on the number of threads). Per-thread
// partial sums would be cheaper to reduce but would make the rounding depend on how the
// elements were split among threads.
//
// A kernel (usually the term itself) provides
//   static constexpr int nodes_per_element, dofs_per_node;   // N = nodes · dofs local DOFs
//   static constexpr ElementSum summation;
//   static constexpr bool zero_energy_is_inactive;  // E = 0 exactly: no gradient, no Hessian
//   static constexpr int parallel_threshold;        // fewer elements: always serial
//   int element_count() const;
//   std::array<int, nodes_per_element> element_nodes(int e) const;   // DOF = dofs·node + k
//   double element(int e, const Eigen::VectorXd& x, Vec<N>* gradient, Mat<N>* hessian,
//                  bool project_psd) const;
// `element` overwrites the outputs it is given (nullptr: not wanted) and returns the element's
// energy (+inf outside its domain). A kernel may return any finite number when it is asked
// for derivatives only and does not compute the energy on the way; an element whose returned
// value is not finite is left out of the gradient and the Hessian.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "numerics/terms/energy_term.hpp"

namespace yarnfit::numerics {

template <int N>
using LocalVector = Eigen::Matrix<double, N, 1>;
template <int N>
using LocalMatrix = Eigen::Matrix<double, N, N>;

// How a term adds its elements' energies to a caller's running total E:
//   per_element: E += e_1, E += e_2, …   (a scene of such terms is one flat sum over all
//                                         elements, as the yarn system's energy (6.8) is)
//   per_term:    E += (e_1 + e_2 + …)    (each term sums its own elements first)
// Both are exact up to rounding; each simulator keeps the order its results were made with.
enum class ElementSum { per_element, per_term };

// Whether a loop over `count` elements should start an OpenMP team.
inline bool parallel_elements(int count, int threshold) {
#ifdef _OPENMP
  return count > threshold && !omp_in_parallel() && omp_get_max_threads() > 1;
#else
  (void)count;
  (void)threshold;
  return false;
#endif
}

template <class Kernel>
constexpr int local_size() {
  return Kernel::nodes_per_element * Kernel::dofs_per_node;
}

// Adds the elements' energies to `energy` (see ElementSum).
template <class Kernel>
void add_element_values(const Kernel& k, const Eigen::VectorXd& x, double& energy) {
  constexpr int N = local_size<Kernel>();
  const int count = k.element_count();
  const auto value_of = [&](int e) {
    return k.element(e, x, static_cast<LocalVector<N>*>(nullptr), static_cast<LocalMatrix<N>*>(nullptr), false);
  };
  if (!parallel_elements(count, Kernel::parallel_threshold)) {
    if constexpr (Kernel::summation == ElementSum::per_element) {
      for (int e = 0; e < count; ++e) energy += value_of(e);
    } else {
      double subtotal = 0.0;
      for (int e = 0; e < count; ++e) subtotal += value_of(e);
      energy += subtotal;
    }
    return;
  }
  std::vector<double> values(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(static)
  for (int e = 0; e < count; ++e) values[static_cast<std::size_t>(e)] = value_of(e);
  if constexpr (Kernel::summation == ElementSum::per_element) {
    for (const double v : values) energy += v;
  } else {
    double subtotal = 0.0;
    for (const double v : values) subtotal += v;
    energy += subtotal;
  }
}

namespace detail {

template <class Kernel>
void scatter_gradient(const Kernel& k, int e, const LocalVector<local_size<Kernel>()>& local, double* gradient) {
  constexpr int D = Kernel::dofs_per_node;
  const auto nodes = k.element_nodes(e);
  for (int i = 0; i < Kernel::nodes_per_element; ++i) {
    const int base = D * nodes[static_cast<std::size_t>(i)];
    for (int d = 0; d < D; ++d) gradient[base + d] += local(D * i + d);
  }
}

// Entries in the order node i, node j, component a, component b (rows and columns of the
// same global DOF may meet twice inside one periodic element; this order sums them as the
// simulators always have).
template <class Kernel>
void append_hessian(const Kernel& k, int e, const LocalMatrix<local_size<Kernel>()>& local, Triplets& out,
                    bool lower_only) {
  constexpr int D = Kernel::dofs_per_node;
  constexpr int NV = Kernel::nodes_per_element;
  const auto nodes = k.element_nodes(e);
  for (int i = 0; i < NV; ++i) {
    const int vi = nodes[static_cast<std::size_t>(i)];
    for (int j = 0; j < NV; ++j) {
      const int vj = nodes[static_cast<std::size_t>(j)];
      if (lower_only && vi < vj) continue;
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b)
          if (!lower_only || D * vi + a >= D * vj + b)
            out.emplace_back(D * vi + a, D * vj + b, local(D * i + a, D * j + b));
    }
  }
}

template <class Kernel>
bool contributes(double energy) {
  if (!std::isfinite(energy)) return false;
  if constexpr (Kernel::zero_energy_is_inactive) return energy != 0.0;
  return true;
}

}  // namespace detail

// Adds the elements' gradients into `g` (#x entries, e.g. a column of a matrix); with
// `energy`, also their energies (one pass, as add_element_values sums them), for kernels
// whose `element` returns the true energy together with the gradient.
template <class Kernel>
void add_element_gradients(const Kernel& k, const Eigen::VectorXd& x, double* g, double* energy = nullptr) {
  constexpr int N = local_size<Kernel>();
  const int count = k.element_count();
  double subtotal = 0.0;
  const auto add_energy = [&](double e) {
    if (energy == nullptr) return;
    if constexpr (Kernel::summation == ElementSum::per_element) *energy += e;
    else subtotal += e;
  };
  if (!parallel_elements(count, Kernel::parallel_threshold)) {
    LocalVector<N> local;
    for (int e = 0; e < count; ++e) {
      const double v = k.element(e, x, &local, static_cast<LocalMatrix<N>*>(nullptr), false);
      add_energy(v);
      if (detail::contributes<Kernel>(v)) detail::scatter_gradient(k, e, local, g);
    }
  } else {
    std::vector<LocalVector<N>> locals(static_cast<std::size_t>(count));
    std::vector<double> values(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(static)
    for (int e = 0; e < count; ++e)
      values[static_cast<std::size_t>(e)] =
          k.element(e, x, &locals[static_cast<std::size_t>(e)], static_cast<LocalMatrix<N>*>(nullptr), false);
    for (int e = 0; e < count; ++e) {
      const double v = values[static_cast<std::size_t>(e)];
      add_energy(v);
      if (detail::contributes<Kernel>(v)) detail::scatter_gradient(k, e, locals[static_cast<std::size_t>(e)], g);
    }
  }
  if constexpr (Kernel::summation == ElementSum::per_term) {
    if (energy != nullptr) *energy += subtotal;
  }
}

// Appends the elements' Hessian blocks (per-element projected on request) to `out`.
template <class Kernel>
void add_element_hessians(const Kernel& k, const Eigen::VectorXd& x, Triplets& out, const HessianOptions& options) {
  constexpr int N = local_size<Kernel>();
  const int count = k.element_count();
  if (!parallel_elements(count, Kernel::parallel_threshold)) {
    LocalMatrix<N> local;
    for (int e = 0; e < count; ++e) {
      local.setZero();
      const double v = k.element(e, x, static_cast<LocalVector<N>*>(nullptr), &local, options.project_psd);
      if (detail::contributes<Kernel>(v)) detail::append_hessian(k, e, local, out, options.lower_only);
    }
    return;
  }
  std::vector<LocalMatrix<N>> locals(static_cast<std::size_t>(count));
  std::vector<double> values(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(static)
  for (int e = 0; e < count; ++e) {
    auto& local = locals[static_cast<std::size_t>(e)];
    local.setZero();
    values[static_cast<std::size_t>(e)] =
        k.element(e, x, static_cast<LocalVector<N>*>(nullptr), &local, options.project_psd);
  }
  for (int e = 0; e < count; ++e)
    if (detail::contributes<Kernel>(values[static_cast<std::size_t>(e)]))
      detail::append_hessian(k, e, locals[static_cast<std::size_t>(e)], out, options.lower_only);
}

// An energy term whose value, gradient and Hessian are the sums over its elements
// (CRTP, after IPC Toolkit's potentials: the derived class describes one element, the sum
// is written once here). `Base` is EnergyTerm or a simulator's extension of it.
template <class Derived, class Base = EnergyTerm>
class ElementTerm : public Base {
 public:
  void add_value(const Eigen::VectorXd& x, double& energy) const override {
    add_element_values(self(), x, energy);
  }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& gradient) const override {
    add_element_gradients(self(), x, gradient.data());
  }
  void add_hessian(const Eigen::VectorXd& x, Triplets& hessian, const HessianOptions& options) const override {
    add_element_hessians(self(), x, hessian, options);
  }
  void add_value_gradient(const Eigen::VectorXd& x, double& energy, Eigen::VectorXd& gradient) const override {
    if constexpr (Derived::energy_with_derivatives) {
      add_element_gradients(self(), x, gradient.data(), &energy);
    } else {
      add_value(x, energy);
      add_gradient(x, gradient);
    }
  }

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
};

}  // namespace yarnfit::numerics
