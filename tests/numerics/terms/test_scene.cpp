// A scene as a list of terms (numerics/terms/scene.hpp): totals in list order, NaN never
// hidden behind +inf, the names that results record as effects, the safe step of the
// terms, and diagnostics that name the offending term.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "numerics/terms/scene.hpp"
#include "tests/support/test_energy_terms.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::numerics {
namespace {

using testing::NanGradientTerm;
using testing::QuadraticTerm;
using testing::WallTerm;

// A term that limits every step to a fixed fraction and whose energy is NaN on request.
class HookTerm final : public EnergyTerm {
 public:
  explicit HookTerm(double fraction, bool nan = false) : m_fraction(fraction), m_nan(nan) {}
  [[nodiscard]] std::string name() const override { return "hook"; }
  void add_value(const Eigen::VectorXd&, double& e) const override {
    e += m_nan ? std::numeric_limits<double>::quiet_NaN() : 1.0;
  }
  void add_gradient(const Eigen::VectorXd&, Eigen::VectorXd&) const override {}
  void add_hessian(const Eigen::VectorXd&, Triplets&, const HessianOptions&) const override {}
  [[nodiscard]] double max_step(const Eigen::VectorXd&, const Eigen::VectorXd&) const override { return m_fraction; }

 private:
  double m_fraction;
  bool m_nan;
};

TEST(Scene, TotalsNamesAndSteps) {
  const QuadraticTerm q(Eigen::MatrixXd::Identity(2, 2), Eigen::Vector2d(1.0, -1.0));
  const HookTerm a(0.5), b(0.25);
  const TermList terms{&q, &a, &b};
  const Eigen::Vector2d x(0.0, 0.0);
  EXPECT_DOUBLE_EQ(total_energy(terms, x), 1.0 + 1.0 + 1.0);
  EXPECT_EQ(total_gradient(terms, x), Eigen::Vector2d(-1.0, 1.0));
  EXPECT_EQ(term_names(terms), (std::vector<std::string>{"quadratic", "hook", "hook"}));
  EXPECT_EQ(max_step(terms, x, Eigen::Vector2d(1.0, 0.0)), 0.25);
  EXPECT_EQ(max_step(TermList{&q}, x, Eigen::Vector2d(1.0, 0.0)), 1.0);
}

TEST(Scene, NanIsNotHiddenAndTheOffendingTermIsNamed) {
  const WallTerm wall(1.0, 1e-3, 3.0);
  const HookTerm nan_term(1.0, true);
  const Eigen::Vector2d beyond(2.0, 0.0);  // +inf for the wall
  EXPECT_TRUE(std::isinf(total_energy(TermList{&wall}, beyond)));
  EXPECT_TRUE(std::isnan(total_energy(TermList{&wall, &nan_term}, beyond)));
  EXPECT_NE(describe_non_finite_values(TermList{&wall}, beyond).find("'wall' = inf"), std::string::npos);
  const NanGradientTerm bad;
  EXPECT_NE(describe_non_finite_gradients(TermList{&bad, &wall}, Eigen::Vector2d(0.9, 0.0)).find("'nan_gradient'"),
            std::string::npos);
  EXPECT_ERROR(check_terms(TermList{}, "test"), yarnfit::ErrorCategory::input);
  EXPECT_ERROR(check_terms(TermList{&wall, nullptr}, "test"), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::numerics
