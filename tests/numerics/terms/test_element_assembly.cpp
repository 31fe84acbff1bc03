// The one assembler (numerics/terms/element_assembly.hpp): the parallel path gives bitwise
// the serial result for any thread count (SPEC §5a), the two summation orders are the ones
// documented, inactive and non-finite elements are left out, and the lower triangle is
// exactly the lower half of the full Hessian.

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "numerics/terms/element_assembly.hpp"

namespace yarnfit::numerics {
namespace {

// Springs of rest length 1 between node pairs in 2-D: E = ½ k (|x_b − x_a| − 1)². Some pairs
// repeat a node (a periodic element may see one vertex twice: its entries are summed in
// order); `zero` elements return exactly 0 energy; one element can be made infinite.
template <ElementSum Sum, bool Inactive>
struct SpringKernel {
  static constexpr int nodes_per_element = 2;
  static constexpr int dofs_per_node = 2;
  static constexpr ElementSum summation = Sum;
  static constexpr bool zero_energy_is_inactive = Inactive;
  static constexpr int parallel_threshold = 16;

  std::vector<std::array<int, 2>> pairs;
  std::vector<double> k;
  int infinite = -1;

  [[nodiscard]] int element_count() const { return static_cast<int>(pairs.size()); }
  [[nodiscard]] std::array<int, 2> element_nodes(int e) const { return pairs[static_cast<std::size_t>(e)]; }
  double element(int e, const Eigen::VectorXd& x, LocalVector<4>* g, LocalMatrix<4>* h, bool) const {
    if (e == infinite) return std::numeric_limits<double>::infinity();
    const auto& p = pairs[static_cast<std::size_t>(e)];
    const double ke = k[static_cast<std::size_t>(e)];
    const Eigen::Vector2d d = x.segment<2>(2 * p[1]) - x.segment<2>(2 * p[0]);
    const double l = d.norm();
    const Eigen::Vector2d n = l > 0 ? Eigen::Vector2d(d / l) : Eigen::Vector2d::UnitX();
    if (g != nullptr) {
      g->segment<2>(0) = -ke * (l - 1.0) * n;
      g->segment<2>(2) = ke * (l - 1.0) * n;
    }
    if (h != nullptr) {
      const Eigen::Matrix2d b = ke * n * n.transpose();
      h->block<2, 2>(0, 0) = b;
      h->block<2, 2>(2, 2) = b;
      h->block<2, 2>(0, 2) = -b;
      h->block<2, 2>(2, 0) = -b;
    }
    return 0.5 * ke * (l - 1.0) * (l - 1.0);
  }
};

template <class Kernel>
Kernel make_kernel(int nodes, int elements, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> node(0, nodes - 1);
  std::uniform_real_distribution<double> stiffness(0.5, 2.0);
  Kernel k;
  for (int e = 0; e < elements; ++e) {
    const int a = node(rng);
    const int b = e % 7 == 0 ? a : node(rng);  // every 7th element: one node twice
    k.pairs.push_back({a, b});
    k.k.push_back(e % 5 == 0 ? 0.0 : stiffness(rng));  // every 5th: zero energy
  }
  return k;
}

Eigen::VectorXd random_state(int nodes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  return Eigen::VectorXd::NullaryExpr(2 * nodes, [&] { return u(rng); });
}

struct Assembled {
  double energy = 0.0;
  double one_pass_energy = 0.0;
  Eigen::VectorXd gradient;
  Triplets hessian;
};

template <class Kernel>
Assembled assemble_with(const Kernel& k, const Eigen::VectorXd& x, int threads, bool lower_only) {
  omp_set_num_threads(threads);
  Assembled a;
  add_element_values(k, x, a.energy);
  a.gradient = Eigen::VectorXd::Zero(x.size());
  add_element_gradients(k, x, a.gradient.data());
  Eigen::VectorXd g2 = Eigen::VectorXd::Zero(x.size());
  add_element_gradients(k, x, g2.data(), &a.one_pass_energy);
  EXPECT_EQ(g2, a.gradient);
  add_element_hessians(k, x, a.hessian, {false, lower_only});
  omp_set_num_threads(1);
  return a;
}

void expect_same_triplets(const Triplets& a, const Triplets& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].row(), b[i].row());
    EXPECT_EQ(a[i].col(), b[i].col());
    EXPECT_EQ(a[i].value(), b[i].value());  // bitwise
  }
}

TEST(ElementAssembly, ParallelIsBitwiseTheSerialResultForAnyThreadCount) {
  using K = SpringKernel<ElementSum::per_element, false>;
  const K k = make_kernel<K>(40, 500, 1);
  const Eigen::VectorXd x = random_state(40, 2);
  const Assembled serial = assemble_with(k, x, 1, true);
  for (const int threads : {2, 3, 4}) {
    const Assembled parallel = assemble_with(k, x, threads, true);
    EXPECT_EQ(parallel.energy, serial.energy) << threads << " threads";
    EXPECT_EQ(parallel.one_pass_energy, serial.one_pass_energy) << threads << " threads";
    EXPECT_EQ(parallel.gradient, serial.gradient) << threads << " threads";
    expect_same_triplets(parallel.hessian, serial.hessian);
  }
}

TEST(ElementAssembly, SummationOrdersAreTheDocumentedOnes) {
  using KE = SpringKernel<ElementSum::per_element, false>;
  using KT = SpringKernel<ElementSum::per_term, false>;
  const KE ke = make_kernel<KE>(10, 60, 3);
  KT kt;
  kt.pairs = ke.pairs;
  kt.k = ke.k;
  const Eigen::VectorXd x = random_state(10, 4);
  const double start = 12345.678;  // a running total from an earlier term
  double flat = start, subtotal = 0.0;
  for (int e = 0; e < ke.element_count(); ++e) {
    const double v = ke.element(e, x, nullptr, nullptr, false);
    flat += v;
    subtotal += v;
  }
  double per_element = start, per_term = start;
  add_element_values(ke, x, per_element);
  add_element_values(kt, x, per_term);
  EXPECT_EQ(per_element, flat);
  EXPECT_EQ(per_term, start + subtotal);
}

TEST(ElementAssembly, InactiveAndNonFiniteElementsAreLeftOut) {
  using K = SpringKernel<ElementSum::per_element, true>;
  K k = make_kernel<K>(12, 40, 5);
  const Eigen::VectorXd x = random_state(12, 6);
  Triplets with_inactive_skipped;
  add_element_hessians(k, x, with_inactive_skipped, {false, false});
  // Elements with k = 0 have exactly zero energy: 8 of 40 leave no entries.
  std::size_t active = 0;
  for (int e = 0; e < k.element_count(); ++e) active += k.k[static_cast<std::size_t>(e)] != 0.0 ? 1 : 0;
  EXPECT_EQ(with_inactive_skipped.size(), active * 16);
  // An infinite element adds +inf to the energy and nothing to gradient or Hessian.
  k.infinite = 3;
  double e = 0.0;
  add_element_values(k, x, e);
  EXPECT_TRUE(std::isinf(e));
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  add_element_gradients(k, x, g.data());
  EXPECT_TRUE(g.allFinite());
}

TEST(ElementAssembly, LowerTriangleIsTheLowerHalfOfTheFullHessian) {
  using K = SpringKernel<ElementSum::per_element, false>;
  const K k = make_kernel<K>(15, 80, 7);
  const Eigen::VectorXd x = random_state(15, 8);
  Triplets full, lower;
  add_element_hessians(k, x, full, {false, false});
  add_element_hessians(k, x, lower, {false, true});
  for (const auto& t : lower) EXPECT_GE(t.row(), t.col());
  Eigen::SparseMatrix<double> f(x.size(), x.size()), l(x.size(), x.size());
  f.setFromTriplets(full.begin(), full.end());
  l.setFromTriplets(lower.begin(), lower.end());
  const Eigen::MatrixXd fd(f), ld(l);
  EXPECT_EQ(Eigen::MatrixXd(fd.triangularView<Eigen::Lower>()), ld);
  EXPECT_LT((fd - fd.transpose()).lpNorm<Eigen::Infinity>(), 1e-14);
}

}  // namespace
}  // namespace yarnfit::numerics
