#include "shell_fit/fit/shell_fit.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::shell {

db::Problems ShellFitOptions::problems() const {
  db::Problems out;
  const auto say = [&out](const char* field, const std::string& message) { out.add("", 0, field, message); };
  if (!(std::isfinite(mesh) && mesh > 0.0)) say("mesh", "must be a positive cell size [m] (got " + db::format_g(mesh) + ")");
  if (refinements < 0 || refinements > 4) say("refinements", "must be 0 to 4 (got " + std::to_string(refinements) + ")");
  if (threads < 1 || threads > 64) say("threads", "must be 1 to 64 (got " + std::to_string(threads) + ")");
  if (max_iterations < 1 || max_iterations > 1000)
    say("max_iterations", "must be 1 to 1000 (got " + std::to_string(max_iterations) + ")");
  check_fab_held_out(fab_held_out, "fab_held_out", out);
  const FabBendOptions& b = fab_bends;
  if (!(b.ktheta_lower > 0.0 && b.ktheta_upper > b.ktheta_lower && std::isfinite(b.ktheta_upper)))
    say("fab_bends.ktheta_lower", "the k_θ search range must be 0 < lower < upper (got " + db::format_g(b.ktheta_lower) +
                                      " to " + db::format_g(b.ktheta_upper) + ")");
  if (b.scan_points < 3 || b.max_evaluations <= b.scan_points)
    say("fab_bends.scan_points", "must be at least 3 and below max_evaluations");
  if (!(b.tolerance > 0.0) || b.points < 2 || !(b.width_over_length > 0.0))
    say("fab_bends", "tolerance and width_over_length must be positive, points at least 2");
  return out;
}

std::string ShellFitResult::failure() const {
  if (!inplane.converged) return "shell fit did not converge: " + inplane.message;
  if (bending && !bending->converged) return "bending fit did not converge: " + bending->message;
  if (fab)
    for (const auto& b : fab->bends)
      if (!b.converged) return "loop-bend fit (" + std::string(db::to_string(b.direction)) + ") did not converge: " + b.message;
  return {};
}

namespace {

// A FAB record's bends (k_θ, unless pear-loop tests gave it) and every test against the model.
void fit_fab_tests(const db::Fabric& fabric, const ShellFitOptions& options, ShellFitResult& result) {
  const auto start = numerics::Clock::now();
  FabRecordFit fab;
  fab.held_out = options.fab_held_out;
  if (!result.has_bending_tests) {
    fab.bends =
        fit_fab_record_bends(fabric, result.params.inplane, options.fab_held_out, options.threads, options.fab_bends);
    for (const auto& b : fab.bends) {
      if (!(b.ktheta > 0.0) || b.tests.empty()) continue;  // no loop of this direction was fitted
      const auto k = static_cast<std::size_t>(b.direction);
      result.params.bending.ktheta[k] = b.ktheta;
      double kappa = 0.0;
      for (const auto& t : b.tests)
        if (t.converged) kappa = std::max(kappa, t.max_curvature);
      if (kappa > 0.0) result.ranges.max_curvature[k] = kappa;
    }
    for (const auto& b : fab.bends)
      if (!b.effects.empty()) result.effects["loop_bend"] = b.effects;
  }
  FabStretchOptions stretch;
  stretch.target_edge = options.mesh;
  fab.tests =
      fab_test_figures(fabric, result.params, fab.bends, options.fab_held_out, options.threads, stretch, options.fab_bends);
  fab.seconds = numerics::seconds_since(start);
  result.seconds += fab.seconds;
  result.fab = std::move(fab);
}

}  // namespace

ShellFitResult fit_shell(const db::Fabric& fabric, const ShellFitOptions& options) {
  if (const auto problems = options.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "shell fit options:\n" + problems.to_string());
  ShellFitResult result;
  result.fabric_id = fabric.id;
  result.family = fabric.family;
  result.has_bending_tests = !fabric.bending_tests.empty();
  // A FAB record: the in-plane fit sees the stretch test it fits, not the one held out.
  const bool fab = !fabric.fab_tests.empty();
  const db::Fabric fab_view = fab ? fab_fit_view(fabric, options.fab_held_out) : db::Fabric{};

  InplaneFitOptions inplane;
  inplane.target_edge = options.mesh;
  inplane.refinements = options.refinements;
  inplane.threads = options.threads;
  inplane.max_iterations = options.max_iterations;
  inplane.model = options.model;
  if (options.full_range) inplane.max_line_force = std::numeric_limits<double>::infinity();
  inplane.progress = options.progress;
  result.inplane = fit_inplane(fab ? fab_view : fabric, inplane);
  result.effects["stretch"] = result.inplane.effects;
  result.seconds = result.inplane.seconds;

  result.params.inplane = result.inplane.params;
  for (const auto& d : result.inplane.directions)
    result.ranges.max_stretch[static_cast<std::size_t>(d.direction)] = d.max_stretch;

  // Bending (6.3.2), fitted separately with the in-plane model held, as in the thesis.
  if (result.has_bending_tests && (result.inplane.converged || result.inplane.hit_iteration_cap)) {
    BendingFitOptions bending;
    bending.threads = options.threads;
    if (options.progress) {
      // The stage's clock: the bending fit counts from its own start.
      const double offset = result.inplane.seconds;
      bending.progress = [fn = options.progress, offset](const numerics::Progress& p) {
        numerics::Progress q = p;
        q.seconds += offset;
        fn(q);
      };
    }
    result.bending = fit_bending(fabric, result.inplane.params, bending);
    result.params.bending = result.bending->params;
    for (std::size_t k = 0; k < 3; ++k) result.ranges.max_curvature[k] = result.bending->max_curvature[k];
    result.effects["pear_loop"] = result.bending->effects;
    result.seconds += result.bending->seconds;
  }
  if (fab && (result.inplane.converged || result.inplane.hit_iteration_cap)) fit_fab_tests(fabric, options, result);
  result.targets = db::as_stored(generate_uniform_targets(result.params, result.ranges));
  return result;
}

std::array<std::optional<double>, k_shell_param_count> read_shell_params(const std::filesystem::path& file, db::Problems& problems) {
  std::array<std::optional<double>, k_shell_param_count> values;
  const std::string label = file.string();
  std::ifstream in(file);
  if (!in) {
    problems.add(label, 0, "file", "cannot be read");
    return values;
  }
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) {
    problems.add(label, 0, "file", "not a JSON object (expected shell_fit.json)");
    return values;
  }
  const nlohmann::json& p = doc.contains("params") ? doc["params"] : doc;
  if (!p.is_object()) {
    problems.add(label, 0, "params", "expected an object of parameter values");
    return values;
  }
  bool any = false;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const char* name = k_shell_param_names[i];
    if (!p.contains(name) || p[name].is_null()) continue;  // null: not fitted
    any = true;
    if (!p[name].is_number()) problems.add(label, 0, std::string("params.") + name, "expected a number");
    else values[i] = p[name].get<double>();
  }
  if (!any) problems.add(label, 0, "params", "none of kxx, kxy, kyy, kss, kn1, kn2, ktheta_* found");
  return values;
}

}  // namespace yarnfit::shell
