// The in-plane fit's search variables (shell_fit/fit/search_map.hpp): p(q) inverts q_of(p), its
// Jacobian matches central differences, and a lock-up stress slot holds the stress at the
// reference strain whatever the rate.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shell_fit/energies/lockup_curve.hpp"
#include "shell_fit/fit/search_map.hpp"

namespace yarnfit::shell {
namespace {

// Every parameter of the stiffening law free (lss/bss too), with values of a knit.
SearchMap::Params knit_params() {
  SearchMap::Params p;
  p << 120.0, 35.0, 400.0, 30.0, 5.0, 8.0, 300.0, 3.0, 600.0, 1.5, 60.0, 2.0, 0.6, -0.3;
  return p;
}

std::vector<int> all_free() {
  std::vector<int> f;
  for (int k = 0; k < k_inplane_param_count; ++k) f.push_back(k);
  return f;
}

TEST(SearchMap, ParamsInvertQAndTheJacobianMatchesDifferences) {
  const std::array<double, 3> x_ref{0.35, 0.12, 0.6};
  for (const InplaneModel model : {InplaneModel::thesis, InplaneModel::stiffening}) {
    const SearchMap map(all_free(), SearchMap::Params::Zero(), model, x_ref);
    const SearchMap::Params p = knit_params();
    const std::vector<double> q = map.q_of(p);
    EXPECT_LE((map.params(q.data()) - p).cwiseAbs().maxCoeff(), 1e-12 * p.cwiseAbs().maxCoeff());
    const Eigen::MatrixXd D = map.jacobian(q.data());
    for (std::size_t j = 0; j < q.size(); ++j) {
      const double h = 1e-6 * std::max(std::abs(q[j]), 1.0);
      auto up = q, down = q;
      up[j] += h;
      down[j] -= h;
      const SearchMap::Params fd = (map.params(up.data()) - map.params(down.data())) / (2 * h);
      for (int k = 0; k < k_inplane_param_count; ++k)
        EXPECT_NEAR(D(k, static_cast<Eigen::Index>(j)), fd[k], 1e-6 * std::max(std::abs(fd[k]), 1.0))
            << k_inplane_param_names[k] << " by slot " << j << ", model " << to_string(model);
    }
  }
}

TEST(SearchMap, ALockupStressSlotHoldsTheStressAtTheReferenceStrain) {
  const std::array<double, 3> x_ref{0.35, 0.12, 0.6};
  const SearchMap map(all_free(), SearchMap::Params::Zero(), InplaneModel::stiffening, x_ref);
  EXPECT_EQ(map.stress_curve(6), 0);
  EXPECT_EQ(map.stress_curve(8), 1);
  EXPECT_EQ(map.stress_curve(10), 2);
  EXPECT_EQ(map.stress_curve(1), -1);
  EXPECT_FALSE(map.log_slot(1));  // the stiffening law's kxy is searched linearly
  EXPECT_TRUE(map.log_slot(0));
  std::vector<double> q = map.q_of(knit_params());
  for (const double b : {0.0, 2.0, 9.0}) {
    q[7] = b;  // the weft rate, at a fixed weft stress slot
    const SearchMap::Params p = map.params(q.data());
    const LockupCurve curve{p[6], p[7], false};
    EXPECT_NEAR(curve.stress(x_ref[0]), q[6], 1e-12 * q[6]) << "b " << b;
  }
  // Without its rate free, a lock-up stiffness is searched as itself (linearly).
  std::vector<int> free = all_free();
  free.erase(free.begin() + 7);
  const SearchMap no_rate(free, knit_params(), InplaneModel::stiffening, x_ref);
  EXPECT_EQ(no_rate.stress_curve(6), -1);
  EXPECT_FALSE(no_rate.log_slot(6));
}

}  // namespace
}  // namespace yarnfit::shell
