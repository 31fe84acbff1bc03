#include "shell_fit/core/shell_params.hpp"

#include <cmath>
#include <numbers>

namespace yarnfit::shell {

double interpolate_ktheta(const BendingParams& p, double angle) {
  constexpr double quarter = std::numbers::pi / 4.0;
  // Fold to [0, π/2]: an edge at angle a behaves as one at −a and at a + π.
  double a = std::fmod(std::abs(angle), std::numbers::pi);
  if (a > std::numbers::pi / 2.0) a = std::numbers::pi - a;
  if (a <= quarter) {
    const double t = a / quarter;
    return (1.0 - t) * p.ktheta[0] + t * p.ktheta[1];
  }
  const double t = (a - quarter) / quarter;
  return (1.0 - t) * p.ktheta[1] + t * p.ktheta[2];
}

}  // namespace yarnfit::shell
