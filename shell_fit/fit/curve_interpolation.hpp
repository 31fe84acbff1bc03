#pragma once
// Reading a measured curve between its points: the fits place their targets at chosen
// stretches or clamp distances and take the measurement there.

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

}  // namespace yarnfit::shell
