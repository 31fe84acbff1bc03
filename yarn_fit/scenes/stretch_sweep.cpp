#include "yarn_fit/scenes/stretch_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/homogenise/sensitivity.hpp"

namespace yarnfit::yarn {

std::vector<double> even_stretches(double max_stretch, int points) {
  if (points < 2) throw Error(ErrorCategory::input, "a stretch curve needs at least 2 points");
  if (!std::isfinite(max_stretch) || max_stretch <= -1.0)
    throw Error(ErrorCategory::input, "the largest stretch must be finite and greater than -1");
  std::vector<double> s(static_cast<std::size_t>(points));
  for (int i = 0; i < points; ++i) s[static_cast<std::size_t>(i)] = max_stretch * i / (points - 1);
  return s;
}

bool predict_equilibrium(YarnSystem& system, const CoarseDeformation& from, const CoarseDeformation& to,
                         Eigen::VectorXd& g) {
  system.set_deformation(from);
  system.rebuild_contacts(g);  // the last solve may have ended its list at another compression
  const EquilibriumSensitivity sens = equilibrium_sensitivity(system, g, {});
  if (!sens.ok) return false;
  const Eigen::Vector4d step = (to.stretch - from.stretch) * stretch_weights(from) +
                               (to.compression - from.compression) * compression_weights(from);
  const Eigen::VectorXd moved = g + sens.state_tangent * step;
  if (!moved.allFinite()) return false;
  g = moved;
  return true;
}

StretchSweep sweep_stretch(YarnSystem& system, double angle, const std::vector<double>& stretches,
                           Eigen::VectorXd& g, const StretchSweepOptions& options) {
  const auto start = numerics::Clock::now();
  StretchSweep out;
  out.points.reserve(stretches.size());
  if (g.size() != system.dof_count()) g = Eigen::VectorXd::Zero(system.dof_count());
  CompressionOptions compression = options.compression;
  if (compression.band_stress == 0.0) compression.band_stress = default_stress_tolerance(system);
  for (std::size_t i = 0; i < stretches.size(); ++i) {
    const CoarseDeformation chi{stretches[i], compression.initial_guess, 0.0, angle};
    const bool predicted = options.predictor && i > 0 && out.points.back().ok;
    Eigen::VectorXd last;
    if (predicted) {
      last = g;
      predict_equilibrium(system, out.points.back().chi, chi, g);
    }
    Sample s = solve_free_compression(system, chi, g, compression, options.solve);
    if (!s.ok && predicted) {
      // The predicted start failed (it may cross a contact barrier, where the energy is
      // infinite): the point again from the last equilibrium, as without the predictor.
      const int iterations = s.newton_iterations, solves = s.solves;
      g = last;
      s = solve_free_compression(system, chi, g, compression, options.solve);
      s.newton_iterations += iterations;
      s.solves += solves;
    }
    if (s.ok) {
      // The next c* is near this one: bracket it with about twice the last change.
      if (i > 0 && out.points.back().ok)
        compression.initial_step = std::clamp(
            2.0 * std::abs(s.chi.compression - out.points.back().chi.compression), 0.002,
            options.compression.initial_step);
      compression.initial_guess = s.chi.compression;
      if (s.stress_c_slope > 0.0) compression.initial_slope = s.stress_c_slope;
    } else {
      ++out.failures;
      s.chi.stretch = stretches[i];
    }
    out.newton_iterations += s.newton_iterations;
    out.solves += s.solves;
    out.points.push_back(s);
    if (options.on_point) options.on_point(i, out.points.back(), g);
  }
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::yarn
