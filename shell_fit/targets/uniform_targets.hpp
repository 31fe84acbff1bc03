#pragma once
// Spatially uniform targets from a fitted shell model (thesis 6.3, eq. 6.3; SPEC §1 step 2).
//
// For a pull along the unit vector u at angle φ from the weft axis (v ⟂ u):
//   F(s, c) = (1 + s) u uᵀ + (1 − c) v vᵀ
//   c*(s)   = argmin_c Ψ_inplane(F(s, c))        (zero orthogonal stress: vᵀ P v = 0)
//   σ_s     = uᵀ P(F(s, c*)) u,  P = ∂Ψ/∂F       [N/m]
// and for bending σ_κ = ∂(k_θ κ²)/∂κ = 2 k_θ κ  [N] over the curvature range of the tests.
// The file these targets are written to, and its reader, are fabrics_db's
// (fabrics_db/targets/uniform_targets.hpp).

#include <optional>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

// The target types live in fabrics_db, which both stages link (fabrics_db/targets/).
using db::BendingPoint;
using db::DirectionTargets;
using db::UniaxialPoint;

// c*(s) and σ_s(s) for one pull angle φ [rad] from the weft axis. `previous_c` seeds the
// search (continuation along s). Never NaN: an unbracketable minimum gives converged = false.
UniaxialPoint uniaxial_point(const InplaneParams& params, double pull_angle, double stretch,
                             double previous_c = 0.0);

struct TargetRanges {
  // Largest stretch per direction (the measured range); absent → no stretch targets.
  std::optional<double> max_stretch[3];
  // Largest curvature per direction seen in the pear-loop fits; absent → no bending targets.
  std::optional<double> max_curvature[3];
  int stretch_samples = 25;
  int curvature_samples = 15;
};

std::vector<DirectionTargets> generate_uniform_targets(const ShellParams& params,
                                                       const TargetRanges& ranges);

}  // namespace yarnfit::shell
