#include "shell_fit/core/shell_params.hpp"

#include <cmath>
#include <numbers>

namespace yarnfit::shell {

std::array<double, k_inplane_param_count> to_array(const InplaneParams& p) {
  return {p.kxx, p.kxy, p.kyy, p.kss, p.kn1, p.kn2, p.lxx, p.bxx, p.lyy, p.byy, p.lss, p.bss, p.axx, p.ayy};
}

InplaneParams inplane_from_array(const std::array<double, k_inplane_param_count>& v) {
  return {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11], v[12], v[13]};
}

const char* to_string(InplaneModel m) { return m == InplaneModel::thesis ? "thesis" : "stiffening"; }

std::optional<InplaneModel> parse_inplane_model(const std::string& name) {
  if (name == "thesis") return InplaneModel::thesis;
  if (name == "stiffening") return InplaneModel::stiffening;
  return std::nullopt;
}

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
