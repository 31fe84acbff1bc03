#include "shell_fit/fit/record_errors.hpp"

#include <limits>
#include <stdexcept>

#include "fabrics_db/records/fabric_summary.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "results/metrics/error_metrics.hpp"
#include "shell_fit/fit/bending_fit.hpp"
#include "shell_fit/fit/inplane_fit.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/pear_loop.hpp"

namespace yarnfit::shell {

RecordErrors simulate_record_errors(const db::Fabric& fabric, const ShellParams& params, const RecordErrorOptions& options) {
  const auto start = numerics::Clock::now();
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  RecordErrors out;
  out.errors = {nan, nan, nan};
  if (!fabric.bending_tests.empty() && !fabric.areal_density)
    throw Error(ErrorCategory::input, "record errors: bending tests without an areal density");
  const auto entry = [&out](const std::string& dir) -> results::ShellDirectionErrors& {
    return out.by_direction.try_emplace(dir, results::ShellDirectionErrors{nan, nan, nan}).first->second;
  };
  const double max_line_force = options.full_range ? std::numeric_limits<double>::infinity() : db::k_power_line_force;
  results::ShellErrorSum force, compression, aspect;
  bool any_compression = false;
  for (const auto& [dir, test] : fabric.stretch_tests) {
    const DirectionFit targets = make_direction_targets(test, max_line_force);
    const ClampedStretchScene scene(stretch_setup(test, options.mesh, 0));
    const ClampedStretchRun run = scene.run(params.inplane, targets.stretch);
    results::ShellDirectionCurves c;
    c.direction = std::string(db::to_string(dir));
    c.fitted_max_stretch = targets.max_stretch;
    c.measured_max_stretch = targets.measured_max_stretch;
    c.stretch = targets.stretch;
    c.measured_force_N = targets.measured_force;
    c.measured_compression = targets.measured_compression;
    if (!run.ok) {
      out.message = c.direction + " stretch test: " + run.message;
      out.curves.push_back(std::move(c));
      continue;
    }
    for (const auto& s : run.samples) {
      c.simulated_force_N.push_back(s.force);
      if (!c.measured_compression.empty()) c.simulated_compression.push_back(s.compression);
    }
    force.add(c.measured_force_N, c.simulated_force_N);
    if (!c.measured_compression.empty()) compression.add(c.measured_compression, c.simulated_compression), any_compression = true;
    auto& e = entry(c.direction);
    e.stretch_force_pct = results::shell_error_pct(c.measured_force_N, c.simulated_force_N);
    e.compression_pct = results::shell_error_pct(c.measured_compression, c.simulated_compression);
    out.curves.push_back(std::move(c));
  }
  for (const auto& [dir, test] : fabric.bending_tests) {
    const BendingDirectionFit targets = make_bending_targets(test);
    PearLoopSetup setup = pear_loop_setup(test, *fabric.areal_density, options.bending_mesh, 0);
    setup.stop_at_first_failure = true;
    const PearLoopScene scene(setup);
    const PearLoopRun run = scene.run(params, targets.clamp_distance);
    results::BendingCurve b;
    b.direction = std::string(db::to_string(dir));
    b.clamp_distance_m = targets.clamp_distance;
    b.measured_aspect_ratio = targets.measured_aspect_ratio;
    if (!run.ok) {
      if (out.message.empty()) out.message = b.direction + " pear loop: " + run.message;
      out.bending.push_back(std::move(b));
      continue;
    }
    for (const auto& s : run.samples) b.simulated_aspect_ratio.push_back(s.aspect_ratio);
    aspect.add(b.measured_aspect_ratio, b.simulated_aspect_ratio);
    entry(b.direction).bending_pct = results::shell_error_pct(b.measured_aspect_ratio, b.simulated_aspect_ratio);
    out.bending.push_back(std::move(b));
  }
  out.ok = out.message.empty();
  if (out.ok) {
    out.errors.stretch_force_pct = force.pct();
    out.errors.compression_pct = any_compression ? compression.pct() : nan;
    out.errors.bending_pct = fabric.bending_tests.empty() ? nan : aspect.pct();
  }
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::shell
