#pragma once
// Parameters of the thin-shell model (thesis 6.3, SPEC §3), SI units.
//
//   Ψ_inplane = ½ εᵀ K ε + kn1 (J − 1)² + kn2 log² J              (6.1)   [J/m² = N/m]
//   K = [[kxx, kxy, 0], [kxy, kyy, 0], [0, 0, kss]],  ε = (E11, E22, 2 E12) in the material
//   frame (weft = x), E = ½ (FᵀF − I), J = area ratio.
//   Ψ_bending = k_θ κ²,  κ = 3θ/H per interior edge, times the incident rest area    (6.4)
//   k_θ [N·m] interpolated linearly in the edge's rest angle between weft, bias, warp.

#include <array>
#include <string>
#include <vector>

namespace yarnfit::shell {

struct InplaneParams {
  double kxx = 0.0;  // [N/m]
  double kxy = 0.0;  // [N/m]
  double kyy = 0.0;  // [N/m]
  double kss = 0.0;  // [N/m]
  double kn1 = 0.0;  // [N/m]
  double kn2 = 0.0;  // [N/m]
};

struct BendingParams {
  // k_θ along weft (0°), bias (45°) and warp (90°) [N·m].
  std::array<double, 3> ktheta{0.0, 0.0, 0.0};
};

struct ShellParams {
  InplaneParams inplane;
  BendingParams bending;
};

// k_θ of an edge whose rest direction makes angle `angle` [rad] with the weft axis: linear in
// the folded angle a ∈ [0, π/2] (edges have no orientation, and the model is symmetric about
// the weft and warp axes), between weft (0), bias (π/4) and warp (π/2).
double interpolate_ktheta(const BendingParams& p, double angle);

}  // namespace yarnfit::shell
