#include "shell_fit/energies/lockup_curve.hpp"

#include <cmath>

namespace yarnfit::shell {

namespace {

// Below this y the series is used: its terms fall by y/(k+n) each, so 40 terms leave less
// than 2^40/40! ≈ 1e-36 of the sum; above it the closed forms lose at most e^{-2} to
// cancellation.
constexpr double k_series_limit = 2.0;
constexpr int k_series_terms = 40;

// Σ_k y^k/(k+n)! and Σ_k k y^{k−1}/(k+n)!.
double series_h(int n, double y) {
  double term = 1.0;
  for (int k = 1; k <= n; ++k) term /= k;  // 1/n!
  double sum = 0.0;
  for (int k = 0; k < k_series_terms; ++k) {
    sum += term;
    term *= y / (k + 1 + n);
  }
  return sum;
}

double series_dh(int n, double y) {
  // d/dy of Σ_k y^k/(k+n)! = Σ_{k≥0} (k+1) y^k/(k+1+n)!
  double term = 1.0;
  for (int k = 1; k <= n + 1; ++k) term /= k;  // 1/(n+1)!
  double sum = 0.0;
  for (int k = 0; k < k_series_terms; ++k) {
    sum += (k + 1) * term;
    term *= y / (k + 2 + n);
  }
  return sum;
}

}  // namespace

double lockup_h(int n, double y) {
  if (y < k_series_limit) return series_h(n, y);
  const double e = std::exp(y);
  // h_1 = (e^y − 1)/y, h_{n+1} = (h_n − 1/n!)/y.
  double h = (e - 1.0) / y;
  double factorial = 1.0;
  for (int k = 2; k <= n; ++k) {
    factorial *= k - 1;
    h = (h - 1.0 / factorial) / y;
  }
  return h;
}

double lockup_dh(int n, double y) {
  if (y < k_series_limit) return series_dh(n, y);
  // y h_n = h_{n−1} − 1/(n−1)! ⇒ h_n' = (h_{n−1} − n h_n)/y, with h_0 = e^y.
  const double lower = n == 1 ? std::exp(y) : lockup_h(n - 1, y);
  return (lower - n * lockup_h(n, y)) / y;
}

// φ = l x³ h_3(bx) ⇒ ∂φ/∂b = l x⁴ h_3'(bx); the same for φ' (x² h_2) and φ'' (x h_1).
double LockupCurve::energy(double x) const {
  if (!(x > 0.0) || l == 0.0) return 0.0;
  const double x3 = x * x * x;
  return rate_derivative ? l * x3 * x * lockup_dh(3, b * x) : l * x3 * lockup_h(3, b * x);
}

double LockupCurve::stress(double x) const {
  if (!(x > 0.0) || l == 0.0) return 0.0;
  const double x2 = x * x;
  return rate_derivative ? l * x2 * x * lockup_dh(2, b * x) : l * x2 * lockup_h(2, b * x);
}

double LockupCurve::tangent(double x) const {
  if (!(x > 0.0) || l == 0.0) return 0.0;
  return rate_derivative ? l * x * x * lockup_dh(1, b * x) : l * x * lockup_h(1, b * x);
}

double LockupCurve::third(double x) const {
  if (!(x > 0.0) || l == 0.0) return 0.0;
  // φ''' = l h_0(bx) = l e^{bx}; ∂/∂b of it is l x e^{bx}.
  const double e = std::exp(b * x);
  return rate_derivative ? l * x * e : l * e;
}

}  // namespace yarnfit::shell
