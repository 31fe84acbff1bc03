#pragma once
// Reading a measured curve between its points: the fits place their targets at chosen
// stretches or clamp distances and take the measurement there.

#include <algorithm>
#include <cmath>
#include <vector>

namespace yarnfit::shell {

// Piecewise-linear y(x) through (xs, ys), xs increasing; held constant beyond the ends.
inline double interpolate_linear(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (x <= xs.front()) return ys.front();
  for (std::size_t i = 1; i < xs.size(); ++i) {
    if (x <= xs[i]) {
      const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
      return ys[i - 1] + t * (ys[i] - ys[i - 1]);
    }
  }
  return ys.back();
}

// Monotone piecewise-cubic y(x) through (xs, ys), xs increasing (Fritsch & Carlson 1980: Hermite
// cubics whose slopes are limited so that no overshoot appears between monotone data); held
// constant beyond the ends. For a model curve sampled at a few points where it bends sharply
// (a loop's force as its strip straightens), whose chords would miss it by several per cent.
inline double interpolate_monotone_cubic(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  const std::size_t n = xs.size();
  if (n < 3) return interpolate_linear(xs, ys, x);
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
  const std::size_t i = hi - 1;
  const auto secant = [&](std::size_t k) { return (ys[k + 1] - ys[k]) / (xs[k + 1] - xs[k]); };
  // The slope at point k: the harmonic mean of its neighbouring secants where they agree in
  // sign (zero where they do not), one-sided at the ends.
  const auto slope = [&](std::size_t k) {
    if (k == 0) return secant(0);
    if (k == n - 1) return secant(n - 2);
    const double a = secant(k - 1), b = secant(k);
    if (a * b <= 0.0) return 0.0;
    const double wa = 2.0 * (xs[k + 1] - xs[k]) + (xs[k] - xs[k - 1]);
    const double wb = (xs[k + 1] - xs[k]) + 2.0 * (xs[k] - xs[k - 1]);
    return (wa + wb) / (wa / a + wb / b);
  };
  const double h = xs[i + 1] - xs[i], t = (x - xs[i]) / h;
  const double h00 = (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t), h10 = t * (1.0 - t) * (1.0 - t);
  const double h01 = t * t * (3.0 - 2.0 * t), h11 = t * t * (t - 1.0);
  return h00 * ys[i] + h10 * h * slope(i) + h01 * ys[i + 1] + h11 * h * slope(i + 1);
}

}  // namespace yarnfit::shell
