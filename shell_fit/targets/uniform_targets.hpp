#pragma once
// Spatially uniform targets from a fitted shell model (thesis 6.3, eq. 6.3; SPEC §1 step 2).
//
// For a pull along the unit vector u at angle φ from the weft axis (v ⟂ u):
//   F(s, c) = (1 + s) u uᵀ + (1 − c) v vᵀ
//   c*(s)   = argmin_c Ψ_inplane(F(s, c))        (zero orthogonal stress: vᵀ P v = 0)
//   σ_s     = uᵀ P(F(s, c*)) u,  P = ∂Ψ/∂F       [N/m]
// and for bending σ_κ = ∂(k_θ κ²)/∂κ = 2 k_θ κ  [N] over the curvature range of the tests.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

struct UniaxialPoint {
  double stretch = 0.0;
  double compression = 0.0;  // zero-orthogonal-stress compression c*
  double stress = 0.0;       // σ_s [N/m]
  bool converged = false;    // the 1-D minimisation met its tolerance
};

// c*(s) and σ_s(s) for one pull angle φ [rad] from the weft axis. `previous_c` seeds the
// search (continuation along s). Never NaN: an unbracketable minimum gives converged = false.
UniaxialPoint uniaxial_point(const InplaneParams& params, double pull_angle, double stretch,
                             double previous_c = 0.0);

struct BendingPoint {
  double curvature = 0.0;  // κ [1/m]
  double stress = 0.0;     // σ_κ = 2 k_θ κ [N]
};

struct DirectionTargets {
  db::Direction direction = db::Direction::weft;
  std::vector<UniaxialPoint> stretch;  // empty when the direction has no stretch range
  std::vector<BendingPoint> bending;   // empty when it has no curvature range
};

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

// uniform_targets.csv: direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,
// stress_kappa_N (kind is "stretch" or "bending"; cells that do not apply are empty).
void write_uniform_targets_csv(const std::vector<DirectionTargets>& targets,
                               const std::filesystem::path& file);

}  // namespace yarnfit::shell
