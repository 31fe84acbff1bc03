#pragma once
// Shared by the yarn element tests (test_biphasic_stretch, test_rod_bending,
// test_contact_barrier): random configurations at the magnitudes of a real yarn tile in SI
// (radius R = 1 mm, edges ~1 mm, ks ~ 1–400 N, kb ~ ks R²/4, kc ~ 1e-2..1e3 · ks2/R) and the
// finite-difference options for them.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <iostream>
#include <random>
#include <string>

#include "tests/support/derivative_check.hpp"
#include "yarn_fit/energies/yarn_elements.hpp"

namespace yarnfit::yarn::fixtures {

using testing::DerivativeCheckOptions;
using testing::ErrorTally;
using testing::expect_element_derivatives;
using testing::min_eigenvalue;

inline constexpr double pi = std::numbers::pi;
inline constexpr double inf = std::numeric_limits<double>::infinity();

inline constexpr double yarn_radius = 1e-3;  // [m]
inline constexpr double edge_length = 1e-3;  // [m]
inline constexpr double ks2 = 400.0;         // [N]

// Steps of the element checks are fractions of a millimetre.
inline DerivativeCheckOptions element_options() {
  DerivativeCheckOptions o;
  o.length_scale = 1e-3;
  return o;
}

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 v(normal(rng), normal(rng), normal(rng));
  while (v.norm() < 1e-3) v = Vec3(normal(rng), normal(rng), normal(rng));
  return v.normalized();
}

inline Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  q.normalize();
  return q.toRotationMatrix();
}

inline double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// A unit vector at angle `angle` from the unit vector u.
inline Vec3 turned(const Vec3& u, double angle, std::mt19937& rng) {
  Vec3 perp = random_unit(rng);
  perp = (perp - perp.dot(u) * u).normalized();
  return std::cos(angle) * u + std::sin(angle) * perp;
}

template <int N>
Vec<N> rotate_blocks(const Eigen::Matrix3d& r, const Vec<N>& v) {
  Vec<N> out;
  for (int k = 0; k < N / 3; ++k) out.template segment<3>(3 * k) = r * v.template segment<3>(3 * k);
  return out;
}

template <int N>
Mat<N> rotate_blocks(const Eigen::Matrix3d& r, const Mat<N>& m) {
  Mat<N> big = Mat<N>::Zero();
  for (int k = 0; k < N / 3; ++k) big.template block<3, 3>(3 * k, 3 * k) = r;
  return big * m * big.transpose();
}

template <int N>
Vec3 block_sum(const Vec<N>& g) {
  Vec3 s = Vec3::Zero();
  for (int k = 0; k < N / 3; ++k) s += g.template segment<3>(3 * k);
  return s;
}

inline void report(const std::string& what, const ErrorTally& tally) {
  std::cout << "[ FD      ] " << what << ": " << tally.count << " configurations, worst gradient "
            << tally.gradient << ", worst Hessian " << tally.hessian << "\n";
}

}  // namespace yarnfit::yarn::fixtures
