#include "results/metrics/error_metrics.hpp"
#include "numerics/util/non_finite.hpp"

#include <cmath>
#include <limits>

namespace yarnfit::results {

namespace {

using numerics::k_nan;

}  // namespace

void ShellErrorSum::add(std::span<const double> measured, std::span<const double> simulated) {
  if (measured.size() != simulated.size()) {
    m_mismatch = true;
    return;
  }
  for (std::size_t i = 0; i < measured.size(); ++i) {
    m_error += std::abs(simulated[i] - measured[i]);
    m_measured += std::abs(measured[i]);
  }
}

double ShellErrorSum::pct() const {
  if (m_mismatch || !(m_measured > 0.0)) return k_nan;
  return 100.0 * m_error / m_measured;  // NaN when any value was NaN
}

double shell_error_pct(std::span<const double> measured, std::span<const double> simulated) {
  ShellErrorSum sum;
  sum.add(measured, simulated);
  return sum.pct();
}

double yarn_error_pct(std::span<const double> simulated, std::span<const double> target, double norm) {
  if (simulated.empty() || simulated.size() != target.size() || !(norm > 0.0)) return k_nan;
  double sum = 0.0;
  for (std::size_t i = 0; i < simulated.size(); ++i) sum += std::abs((simulated[i] - target[i]) / norm);
  return 100.0 * sum / static_cast<double>(simulated.size());
}

double yarn_error_pct_normalised_after(std::span<const double> simulated, std::span<const double> target,
                                       double norm) {
  if (simulated.empty() || simulated.size() != target.size() || !(norm > 0.0)) return k_nan;
  double sum = 0.0;
  for (std::size_t i = 0; i < simulated.size(); ++i) sum += std::abs(simulated[i] - target[i]);
  return 100.0 * sum / static_cast<double>(simulated.size()) / norm;
}

double mean_over_directions(std::span<const double> per_direction) {
  if (per_direction.empty()) return k_nan;
  double sum = 0.0;
  for (double v : per_direction) sum += v;
  return sum / static_cast<double>(per_direction.size());
}

nlohmann::json pct_json(double pct) { return std::isfinite(pct) ? nlohmann::json(pct) : nlohmann::json(); }

double number_or_nan(const nlohmann::json& value) { return value.is_number() ? value.get<double>() : k_nan; }

}  // namespace yarnfit::results
