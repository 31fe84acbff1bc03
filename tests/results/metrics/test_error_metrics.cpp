// The SPEC error metrics (results/metrics/error_metrics.hpp): known values, several curves
// summed as one, and no figure (NaN, null in JSON) wherever there is nothing to compare.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "results/metrics/error_metrics.hpp"

namespace yarnfit::results {
namespace {

using nlohmann::json;
constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

TEST(ShellErrorMetric, MeanAbsoluteErrorOverMeanAbsoluteMeasured) {
  // Σ|sim − meas| = 0.1 + 0.2 + 0.3 = 0.6, Σ|meas| = 6: 10 %.
  EXPECT_NEAR(shell_error_pct(std::vector<double>{1, 2, 3}, std::vector<double>{1.1, 1.8, 3.3}), 10.0, 1e-12);
  // Signs do not cancel, and the measured magnitude is |meas|.
  EXPECT_NEAR(shell_error_pct(std::vector<double>{-2, 2}, std::vector<double>{-1, 3}), 50.0, 1e-12);
}

TEST(ShellErrorMetric, CurvesAddedTogetherWeighTheirTargetsNotTheirCurves) {
  // Over all targets (Fig. 6.13), not the mean of the per-curve figures: (1 + 0) / (10 + 90).
  ShellErrorSum all;
  all.add(std::vector<double>{10}, std::vector<double>{11});
  all.add(std::vector<double>{30, 60}, std::vector<double>{30, 60});
  EXPECT_NEAR(all.pct(), 1.0, 1e-12);
  // Bit for bit the sums the fits used to write out by hand.
  double err = 0.0, meas = 0.0;
  for (auto [m, s] : {std::pair{10.0, 11.0}, {30.0, 30.0}, {60.0, 60.0}}) {
    err += std::abs(s - m);
    meas += std::abs(m);
  }
  EXPECT_EQ(all.pct(), 100.0 * err / meas);
}

TEST(ShellErrorMetric, NoFigureWithoutSomethingToCompare) {
  EXPECT_TRUE(std::isnan(ShellErrorSum{}.pct()));  // nothing measured
  EXPECT_TRUE(std::isnan(shell_error_pct(std::vector<double>{0, 0}, std::vector<double>{1, 1})));
  EXPECT_TRUE(std::isnan(shell_error_pct(std::vector<double>{1, 2}, std::vector<double>{1})));  // curve missing a point
  EXPECT_TRUE(std::isnan(shell_error_pct(std::vector<double>{1, 2}, std::vector<double>{1, k_nan})));
  ShellErrorSum partly;  // one bad curve spoils the sum
  partly.add(std::vector<double>{1}, std::vector<double>{1});
  partly.add(std::vector<double>{1, 2}, std::vector<double>{});
  EXPECT_TRUE(std::isnan(partly.pct()));
}

TEST(YarnErrorMetric, MeanAbsoluteErrorOverTheNorm) {
  // |1 − 0| / 4 = 0.25 and |2 − 4| / 4 = 0.5: mean 0.375, 37.5 %.
  const std::vector<double> sim{1, 2}, target{0, 4};
  EXPECT_NEAR(yarn_error_pct(sim, target, 4.0), 37.5, 1e-12);
  EXPECT_NEAR(yarn_error_pct_normalised_after(sim, target, 4.0), 37.5, 1e-12);
  // Bit for bit the objective's order: each difference normalised, summed, then 100 · sum / n.
  const std::vector<double> a{0.1, 0.7, 1.3}, b{0.3, 0.2, 1.0};
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs((a[i] - b[i]) / 3.0);
  EXPECT_EQ(yarn_error_pct(a, b, 3.0), 100.0 * sum / 3.0);
  sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
  EXPECT_EQ(yarn_error_pct_normalised_after(a, b, 3.0), 100.0 * sum / 3 / 3.0);
}

TEST(YarnErrorMetric, NoFigureWithoutSamplesOrNorm) {
  EXPECT_TRUE(std::isnan(yarn_error_pct(std::vector<double>{}, std::vector<double>{}, 1.0)));
  EXPECT_TRUE(std::isnan(yarn_error_pct(std::vector<double>{1}, std::vector<double>{1, 2}, 1.0)));
  EXPECT_TRUE(std::isnan(yarn_error_pct(std::vector<double>{1}, std::vector<double>{1}, 0.0)));
  EXPECT_TRUE(std::isnan(yarn_error_pct_normalised_after(std::vector<double>{1}, std::vector<double>{2}, 0.0)));
  EXPECT_TRUE(std::isnan(yarn_error_pct(std::vector<double>{k_nan}, std::vector<double>{1}, 1.0)));
}

TEST(YarnErrorMetric, OverallIsTheMeanOverDirections) {
  EXPECT_NEAR(mean_over_directions(std::vector<double>{10, 20, 30}), 20.0, 1e-12);
  EXPECT_TRUE(std::isnan(mean_over_directions(std::vector<double>{})));
  EXPECT_TRUE(std::isnan(mean_over_directions(std::vector<double>{10, k_nan})));
}

TEST(ErrorMetricJson, NullWhereThereIsNoFigure) {
  EXPECT_TRUE(pct_json(k_nan).is_null());
  EXPECT_TRUE(pct_json(std::numeric_limits<double>::infinity()).is_null());
  EXPECT_EQ(pct_json(1.5), json(1.5));
  EXPECT_EQ(pct_json(0.0), json(0.0));  // a perfect fit is 0, and only then
  EXPECT_TRUE(std::isnan(number_or_nan(json())));
  EXPECT_TRUE(std::isnan(number_or_nan(json("1"))));
  EXPECT_EQ(number_or_nan(json(2.5)), 2.5);
}

}  // namespace
}  // namespace yarnfit::results
