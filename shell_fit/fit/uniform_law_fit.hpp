#pragma once
// A shell law fitted to uniform samples: the inverse of generate_uniform_targets (issue 48).
//
// A fitted yarn model is homogenised back this way: its own uniform responses (σ_s(s) and the
// free compression c*(s) per pull direction, Δσ_κ(κ) per bending direction) become the samples,
// and the law that reproduces them best is what the record's clamped-stretch and pear-loop
// scenes then run with (record_errors.hpp), so that a yarn model is compared with the
// measurements themselves, not only with the targets it was fitted to.
//
// In-plane: Ceres least squares over the law's parameters (stiffnesses and lock-up growths in
// log space, lock-up rates and shares as they are), residuals (σ_law − σ)/σ_norm and
// (c_law − c)/c_norm at every sample, the norms the largest |σ| and |c| (≥ 1e-3) of the
// direction. What the samples cannot determine is held at the start: kss (and the shear
// lock-up) without bias samples, kxx (and the weft lock-up and share) without weft samples,
// kyy (and the warp's) without warp samples. The stiffening law is fitted from the thesis law's fit, as the
// shell stage does. Bending: k_θ of each direction in closed form, Δσ_κ = 2 k_θ κ in the least
// squares sense.

#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/targets/uniform_targets.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

struct UniformLawFit {
  bool ok = false;
  std::string message;  // why not
  InplaneModel model = InplaneModel::stiffening;
  ShellParams params;
  // How far the law is from the samples, the yarn metric (mean |error| over the largest
  // sample, per direction, then the mean over directions) [%]; NaN where there is no sample.
  double stress_misfit_pct = 0.0;
  double compression_misfit_pct = 0.0;
  double bending_misfit_pct = 0.0;
  std::vector<std::string> held;  // parameters the samples do not determine, held at the start
  int iterations = 0;
};

// `start`: where the in-plane fit begins (e.g. the shell stage's own fit); without one, a
// guess from the samples' initial slopes. Never throws for numerical trouble.
UniformLawFit fit_law_to_samples(const std::vector<db::DirectionTargets>& samples, InplaneModel model,
                                 const std::optional<InplaneParams>& start = std::nullopt);

}  // namespace yarnfit::shell
