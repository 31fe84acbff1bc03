#pragma once
// What one run of a shell scene reports (SPEC §5 `yarnfit shell sim`): per stretch the clamp
// force, line force, compression, convergence, Newton iterations, residual and time; per
// clamp distance the aspect ratio r = h/p, h, p and the largest curvature; the effects the
// scene simulated and its mesh.

#include <vector>

#include <nlohmann/json.hpp>

#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/pear_loop.hpp"

namespace yarnfit::shell {

// {kxx, kxy, kyy, kss, kn1, kn2, ktheta_weft, ktheta_bias, ktheta_warp}, the keys of
// shell_fit.json's params.
nlohmann::json params_json(const ShellParams& params);

// The clamped stretch run at `stretches` (one entry each; those after a failure say they were
// not simulated): scene, effects, mesh, converged, message, samples, newton_iterations,
// seconds.
nlohmann::json stretch_run_json(const ClampedStretchSetup& setup, const ClampedStretchScene& scene,
                                const std::vector<double>& stretches, const ClampedStretchRun& run);

// The pear-loop run: scene, effects, areal density, mesh, the governing and effective k_θ,
// the bending length, converged, message, samples, newton_iterations, seconds.
nlohmann::json pear_run_json(const PearLoopSetup& setup, const PearLoopScene& scene, const BendingParams& bending,
                             const PearLoopRun& run);

}  // namespace yarnfit::shell
