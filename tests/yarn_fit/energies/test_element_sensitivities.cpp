// Parameter derivatives of the yarn elements (yarn_elements.hpp: the fit's sensitivities):
// ∂W/∂θ and ∂(∇ₓW)/∂θ against central differences in θ, for every parameter each element
// depends on, over random configurations in every branch (stretch: compressed, soft phase,
// stiff phase; contact: inside R1 only, inside R2 too, beyond the cutoff).

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>
#include <utility>

#include "tests/support/parameter_check.hpp"
#include "tests/yarn_fit/energies/element_fixtures.hpp"

namespace yarnfit::yarn {
namespace {

using namespace fixtures;
using testing::sweep_parameter;

constexpr double kTolerance = 1e-6;

// Tallies the worst error over configurations, reporting the worst one's label.
struct Worst {
  double error = 0.0;
  std::string where;
  void take(double e, const std::string& label) {
    if (e > error) {
      error = e;
      where = label;
    }
  }
};

TEST(ElementSensitivity, StretchMatchesDifferencesInKs1EpsSAndKs2) {
  std::mt19937 rng(11);
  const BiphasicStretch base{.ks1 = 20.0, .ks2 = ks2, .eps_s = 0.02};
  Worst value, gradient;
  int count = 0;
  for (const double strain : {-0.03, -0.002, 0.004, 0.015, 0.019, 0.021, 0.05, 0.2}) {
    for (int trial = 0; trial < 3; ++trial, ++count) {
      const Vec3 x0 = 1e-3 * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      const Vec3 x1 = x0 + (1.0 + strain) * edge_length * random_unit(rng);
      Vec<3> d_energy;
      Eigen::Matrix<double, 6, 3> d_gradient;
      ASSERT_TRUE(stretch_element_sensitivity(x0, x1, edge_length, base, d_energy, d_gradient));
      for (int k = 0; k < 3; ++k) {
        const auto eval = [&](double theta) {
          BiphasicStretch m = base;
          (k == 0 ? m.ks1 : k == 1 ? m.eps_s : m.ks2) = theta;
          Vec<6> g;
          const double w = stretch_element(x0, x1, edge_length, m, &g, nullptr, false);
          return std::pair<double, Eigen::VectorXd>{w, g};
        };
        const double theta = k == 0 ? base.ks1 : k == 1 ? base.eps_s : base.ks2;
        // A derivative that is zero on this branch is compared on the scale of the energy's.
        const double floor = 1e-9 * edge_length * ks2;
        // Steps small enough to stay on ε's branch (the nearest kink is 1e-3 away in ε).
        const auto r = sweep_parameter(eval, theta, d_energy[k], d_gradient.col(k), floor, floor / edge_length,
                                       {1e-3, 1e-4, 1e-5, 1e-6, 1e-7});
        const std::string label = "strain " + std::to_string(strain) + ", parameter " + std::to_string(k);
        value.take(r.value_error, label);
        gradient.take(r.vector_error, label);
      }
    }
  }
  std::cout << "[ FD      ] stretch: " << count << " configurations, worst energy " << value.error << " ("
            << value.where << "), worst gradient " << gradient.error << " (" << gradient.where << ")\n";
  EXPECT_LT(value.error, kTolerance) << value.where;
  EXPECT_LT(gradient.error, kTolerance) << gradient.where;
}

TEST(ElementSensitivity, BendingIsLinearInKb) {
  std::mt19937 rng(5);
  Worst value, gradient;
  for (int trial = 0; trial < 12; ++trial) {
    const Vec3 x1 = 1e-3 * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Vec3 a = random_unit(rng);
    const Vec3 x0 = x1 - edge_length * a;
    const Vec3 x2 = x1 + 1.1 * edge_length * turned(a, uniform(rng, 0.05, 2.0), rng);
    const double rest_magnitude = trial % 3 == 0 ? 0.0 : uniform(rng, 0.1, 1.5);
    const double rest_angle = uniform(rng, -pi, pi);
    const Eigen::Vector2d rest_curvature = rest_magnitude * Eigen::Vector2d(std::cos(rest_angle), std::sin(rest_angle));
    const EdgeAnchor in = anchor_along(turned(a, uniform(rng, 0.0, 0.5), rng));
    const CornerFrames frames{in, carried_anchor(in, Eigen::Matrix3d::Identity(), x2 - x1)};
    double d_energy = 0.0;
    Vec<9> d_gradient;
    ASSERT_TRUE(bending_element_sensitivity(x0, x1, x2, edge_length, 0.9 * edge_length, frames, rest_curvature,
                                            d_energy, d_gradient));
    const double kb = 0.1 * ks2 * yarn_radius * yarn_radius / 4.0;
    const auto eval = [&](double theta) {
      Vec<9> g;
      const double w = bending_element(x0, x1, x2, edge_length, 0.9 * edge_length, frames, rest_curvature,
                                       RodBending{theta}, &g, nullptr, false);
      return std::pair<double, Eigen::VectorXd>{w, g};
    };
    const auto r = sweep_parameter(eval, kb, d_energy, d_gradient, 1e-300, 1e-300);
    value.take(r.value_error, "trial " + std::to_string(trial));
    gradient.take(r.vector_error, "trial " + std::to_string(trial));
  }
  EXPECT_LT(value.error, kTolerance) << value.where;
  EXPECT_LT(gradient.error, kTolerance) << gradient.where;
}

TEST(ElementSensitivity, ContactMatchesDifferencesInBothBarriers) {
  std::mt19937 rng(9);
  const TwoBarrierContact base{.kc1 = 2.0 * ks2 / yarn_radius, .r1 = yarn_radius,
                               .kc2 = 1e3 * ks2 / yarn_radius, .r2 = 0.25 * yarn_radius};
  Worst value, gradient;
  int count = 0, beyond = 0;
  // Closest approach from inside the stiff barrier (D < 2 R2) to beyond the soft one's cutoff.
  for (const double d : {0.3e-3, 0.45e-3, 0.8e-3, 1.2e-3, 1.7e-3, 1.95e-3, 2.5e-3}) {
    for (int trial = 0; trial < 3; ++trial, ++count) {
      const Vec3 a0 = Vec3(-0.5e-3, 0, 0), a1 = Vec3(0.5e-3, 0, 0);
      const Vec3 dir = turned(Vec3::UnitX(), uniform(rng, 0.2, 1.5), rng);
      const Vec3 mid = Vec3(uniform(rng, -1e-4, 1e-4), 0, 0) + d * Vec3(0, 0.3, 1.0).normalized();
      const Vec3 b0 = mid - 0.5e-3 * dir, b1 = mid + 0.6e-3 * dir;
      Vec<4> d_energy;
      Eigen::Matrix<double, 12, 4> d_gradient;
      ASSERT_TRUE(contact_element_sensitivity(a0, a1, b0, b1, edge_length, 1.1 * edge_length, base, d_energy,
                                              d_gradient));
      if (d_energy.isZero() && d_gradient.isZero()) ++beyond;
      for (int k = 0; k < 4; ++k) {
        const auto eval = [&](double theta) {
          TwoBarrierContact m = base;
          (k == 0 ? m.kc1 : k == 1 ? m.r1 : k == 2 ? m.kc2 : m.r2) = theta;
          Vec<12> g;
          const double w = contact_element(a0, a1, b0, b1, edge_length, 1.1 * edge_length, m, &g, nullptr, false);
          return std::pair<double, Eigen::VectorXd>{w, g};
        };
        const double theta = k == 0 ? base.kc1 : k == 1 ? base.r1 : k == 2 ? base.kc2 : base.r2;
        const double floor = 1e-12 * ks2 * edge_length;  // the energies here are ~1e-4 J and up
        const auto r = sweep_parameter(eval, theta, d_energy[k], d_gradient.col(k), floor / std::abs(theta),
                                       floor / std::abs(theta) / edge_length, {1e-4, 1e-5, 1e-6, 1e-7});
        const std::string label = "D " + std::to_string(d) + ", parameter " + std::to_string(k);
        value.take(r.value_error, label);
        gradient.take(r.vector_error, label);
      }
    }
  }
  std::cout << "[ FD      ] contact: " << count << " configurations (" << beyond << " beyond the cutoff), worst energy "
            << value.error << " (" << value.where << "), worst gradient " << gradient.error << " (" << gradient.where
            << ")\n";
  EXPECT_GT(beyond, 0);
  EXPECT_LT(count - beyond, count);
  EXPECT_LT(value.error, kTolerance) << value.where;
  EXPECT_LT(gradient.error, kTolerance) << gradient.where;
}

}  // namespace
}  // namespace yarnfit::yarn
