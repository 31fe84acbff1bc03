#pragma once
// Parameters of the thin-shell model (thesis 6.3, SPEC §3), SI units.
//
//   Ψ_inplane = ½ εᵀ K ε + kn1 (J − 1)² + kn2 log² J              (6.1)   [J/m² = N/m]
//             + φ(ε1 + axx ε2; lxx, bxx) + φ(ε2 + ayy ε1; lyy, byy) + φ(|ε3|; lss, bss)
//                                                                  lock-up ("stiffening" model)
//   K = [[kxx, kxy, 0], [kxy, kyy, 0], [0, 0, kss]],  ε = (E11, E22, 2 E12) in the material
//   frame (weft = x), E = ½ (FᵀF − I), J = area ratio.
//   The lock-up terms (shell_fit/energies/lockup_curve.hpp) act on the weft strain measure
//   ε1 + axx ε2, the warp one ε2 + ayy ε1 and the shear |ε3|, each only where positive; with
//   l = 0 they vanish and Ψ is eq. 6.1. The lateral shares a ≥ 0 say how much of a loop's
//   lock-up a narrowing across the pull relieves: a jammed loop can still lengthen by
//   narrowing, so the lock-up pulls the width in and the contraction grows with the pull.
//   Ψ_bending = k_θ κ²,  κ = 3θ/H per interior edge, times the incident rest area    (6.4)
//   k_θ [N·m] interpolated linearly in the edge's rest angle between weft, bias, warp.

#include <array>
#include <optional>
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
  // Lock-up terms (zero in the thesis model): stiffness growth l [N/m] and rate b [-] along
  // weft (xx), warp (yy) and shear (ss).
  double lxx = 0.0, bxx = 0.0;
  double lyy = 0.0, byy = 0.0;
  double lss = 0.0, bss = 0.0;
  // Lateral shares [-] of the weft and warp lock-up strains (0: the lock-up sees the pulled
  // direction alone).
  double axx = 0.0, ayy = 0.0;
};

// The in-plane parameters as a vector, in the order of k_inplane_param_names: the six of
// eq. 6.1, then the lock-up pairs, then the lock-up's lateral shares. The fit, the scenes'
// sensitivities and the JSON use it.
inline constexpr int k_inplane_param_count = 14;
inline constexpr const char* k_inplane_param_names[k_inplane_param_count] = {
    "kxx", "kxy", "kyy", "kss", "kn1", "kn2", "lxx", "bxx", "lyy", "byy", "lss", "bss", "axx", "ayy"};
// Index of the first lock-up parameter; the thesis model has the first six only.
inline constexpr int k_first_lockup_param = 6;
std::array<double, k_inplane_param_count> to_array(const InplaneParams& p);
InplaneParams inplane_from_array(const std::array<double, k_inplane_param_count>& v);
// The lock-up rates b and lateral shares a enter nonlinearly; every other parameter enters Ψ
// linearly.
constexpr bool is_lockup_rate(int k) { return k == 7 || k == 9 || k == 11; }
// Index of the first lateral share (axx, then ayy).
inline constexpr int k_first_share_param = 12;
constexpr bool is_lockup_share(int k) { return k == k_first_share_param || k == k_first_share_param + 1; }
constexpr bool enters_linearly(int k) { return !is_lockup_rate(k) && !is_lockup_share(k); }
// The lock-up curve (0 weft, 1 warp, 2 shear) a lock-up parameter belongs to.
constexpr int lockup_curve_of(int k) { return is_lockup_share(k) ? k - k_first_share_param : (k - k_first_lockup_param) / 2; }

// Which in-plane law a fit uses: eq. 6.1 alone ("thesis"), or with the lock-up terms
// ("stiffening").
enum class InplaneModel { thesis, stiffening };
const char* to_string(InplaneModel m);
// "thesis" or "stiffening"; nullopt otherwise.
std::optional<InplaneModel> parse_inplane_model(const std::string& name);

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
