#include "shell_fit/fit/shell_fit.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::shell {

db::Problems ShellFitOptions::problems() const {
  db::Problems out;
  const auto say = [&out](const char* field, const std::string& message) { out.add("", 0, field, message); };
  if (!(std::isfinite(mesh) && mesh > 0.0)) say("mesh", "must be a positive cell size [m] (got " + db::format_g(mesh) + ")");
  if (refinements < 0 || refinements > 4) say("refinements", "must be 0 to 4 (got " + std::to_string(refinements) + ")");
  if (threads < 1 || threads > 64) say("threads", "must be 1 to 64 (got " + std::to_string(threads) + ")");
  if (max_iterations < 1 || max_iterations > 1000)
    say("max_iterations", "must be 1 to 1000 (got " + std::to_string(max_iterations) + ")");
  return out;
}

std::string ShellFitResult::failure() const {
  if (!inplane.converged) return "shell fit did not converge: " + inplane.message;
  if (bending && !bending->converged) return "bending fit did not converge: " + bending->message;
  return {};
}

ShellFitResult fit_shell(const db::Fabric& fabric, const ShellFitOptions& options) {
  if (const auto problems = options.problems(); !problems.empty())
    throw std::invalid_argument("shell fit options:\n" + problems.to_string());
  ShellFitResult result;
  result.fabric_id = fabric.id;
  result.family = fabric.family;
  result.has_bending_tests = !fabric.bending_tests.empty();

  InplaneFitOptions inplane;
  inplane.target_edge = options.mesh;
  inplane.refinements = options.refinements;
  inplane.threads = options.threads;
  inplane.max_iterations = options.max_iterations;
  inplane.model = options.model;
  if (options.full_range) inplane.max_line_force = std::numeric_limits<double>::infinity();
  inplane.progress = options.progress;
  result.inplane = fit_inplane(fabric, inplane);
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
      bending.progress = [fn = options.progress, offset](const reports::Progress& p) {
        reports::Progress q = p;
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
