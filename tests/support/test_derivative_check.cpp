// The project's one finite-difference check (tests/support/derivative_check.hpp) must catch
// a gradient or a Hessian that is wrong by 1e-4: it is what every term's test relies on.

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>

#include "tests/support/derivative_check.hpp"

namespace yarnfit::testing {
namespace {

// E = Σ x_i³ with a deliberately wrong gradient or Hessian (relative error 1e-4).
class CubicTerm final : public numerics::EnergyTerm {
 public:
  CubicTerm(double gradient_error, double hessian_error)
      : m_gradient_error(gradient_error), m_hessian_error(hessian_error) {}
  [[nodiscard]] std::string name() const override { return "cubic"; }
  void add_value(const Eigen::VectorXd& x, double& energy) const override { energy += x.array().cube().sum(); }
  void add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g.array() += 3.0 * (1.0 + m_gradient_error) * x.array().square();
  }
  void add_hessian(const Eigen::VectorXd& x, numerics::Triplets& h, const numerics::HessianOptions&) const override {
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      h.emplace_back(static_cast<int>(i), static_cast<int>(i),
                     6.0 * (1.0 + m_hessian_error) * std::abs(x(i)));
    }
  }

 private:
  double m_gradient_error, m_hessian_error;
};

TEST(EnergyDerivativeCheckTest, DetectsWrongDerivatives) {
  const Eigen::VectorXd x = Eigen::Vector3d(0.3, 0.7, 1.1);
  DerivativeCheckOptions o;
  o.check_psd_projection = false;
  expect_derivatives_match(CubicTerm(0.0, 0.0), x, o);  // x > 0: |x| = x, all consistent
  o.check_hessian = false;
  EXPECT_NONFATAL_FAILURE(expect_derivatives_match(CubicTerm(1e-4, 0.0), x, o),
                          "gradient vs FD of value");
  o.check_hessian = true;
  EXPECT_NONFATAL_FAILURE(expect_derivatives_match(CubicTerm(0.0, 1e-4), x, o),
                          "Hessian vs FD of gradient");
}

}  // namespace
}  // namespace yarnfit::testing
