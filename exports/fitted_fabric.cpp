#include "exports/fitted_fabric.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "fabrics_db/records/fabric_hash.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "numerics/roots/bisection.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::exports {

namespace fs = std::filesystem;

namespace {

const std::array<const char*, 3> k_ktheta_names{"ktheta_weft", "ktheta_bias", "ktheta_warp"};

// The fitted value of `name`; an in-plane parameter of the model that was not fitted refuses
// the folder (lock-up terms a thesis-model file leaves out are zero).
double fitted(const results::ShellFitFile& file, const std::string& name, bool required, const fs::path& source) {
  const auto it = file.params.find(name);
  if (it != file.params.end() && it->second) return *it->second;
  if (required) throw Error(ErrorCategory::input, source.string() + ": params." + name + ": not fitted");
  return 0.0;
}

shell::ShellParams fitted_params(const results::ShellFitFile& file, const fs::path& source) {
  std::array<double, shell::k_inplane_param_count> v{};
  for (int k = 0; k < shell::k_inplane_param_count; ++k)
    v[static_cast<std::size_t>(k)] = fitted(file, shell::k_inplane_param_names[k], k < shell::k_first_lockup_param, source);
  shell::ShellParams p;
  p.inplane = shell::inplane_from_array(v);
  for (std::size_t d = 0; d < 3; ++d) p.bending.ktheta[d] = fitted(file, k_ktheta_names[d], false, source);
  return p;
}

}  // namespace

FittedFabric read_fitted_fabric(const fs::path& fit_dir, const fs::path& record) {
  if (!fs::is_directory(fit_dir)) throw Error(ErrorCategory::input, fit_dir.string() + ": not a folder");
  const fs::path shell_file = fit_dir / "shell_fit.json";
  const fs::path yarn_file = fit_dir / "yarn_fit.json";
  if (!fs::exists(shell_file)) {
    if (fs::exists(yarn_file))
      throw Error(ErrorCategory::input, fit_dir.string() +
                                            ": only the yarn stage ran here (no shell_fit.json): the formats are "
                                            "sampled from the fitted shell law; export the folder of a whole fit");
    throw Error(ErrorCategory::input, fit_dir.string() + ": no shell_fit.json: not the folder of a fit");
  }
  FittedFabric f;
  f.folder = fit_dir;
  try {
    f.shell = results::read_shell_fit_file(shell_file);
  } catch (const std::exception& e) {
    throw Error(ErrorCategory::input, e.what());
  }
  const bool usable = f.shell.converged || f.shell.hit_iteration_cap;
  if (!usable) throw Error(ErrorCategory::input, shell_file.string() + ": the shell fit failed: " + f.shell.message);
  const auto model = shell::parse_inplane_model(f.shell.model);
  if (!model) throw Error(ErrorCategory::input, shell_file.string() + ": model: " + f.shell.model + ": not a shell model");
  f.model = *model;
  f.params = fitted_params(f.shell, shell_file);
  if (fs::exists(yarn_file)) {
    try {
      results::YarnFitFile yarn = results::read_yarn_fit_file(yarn_file);
      if (yarn.ok) f.yarn = std::move(yarn);
    } catch (const std::exception& e) {
      throw Error(ErrorCategory::input, e.what());
    }
  }
  if (!record.empty()) {
    const db::FabricLoad load = db::load_fabric(record);
    if (!load.ok()) throw Error(ErrorCategory::input, record.string() + ": the record cannot be read:\n" + load.problems.to_string());
    if (load.fabric->id != f.shell.fabric)
      throw Error(ErrorCategory::input, record.string() + ": the record is " + load.fabric->id + ", the fit is of " + f.shell.fabric);
    f.record = record.string();
    f.record_sha256 = db::fabric_hash(load, nullptr);
    f.areal_density = load.fabric->areal_density;
    f.record_fabric = *load.fabric;
  }
  return f;
}

namespace {

// Along the law's uniaxial curve at `angle` to the comfort line force, at most to `end`:
// steps to the first stretch past it, then bisection.
double comfort_end(const shell::InplaneParams& law, double angle, double end) {
  if (end <= 0.0) return 0.0;
  const auto below = [&](double s) -> std::optional<bool> {
    const db::UniaxialPoint p = shell::uniaxial_point(law, angle, s);
    if (!p.converged) return std::nullopt;
    return p.stress < k_comfort_line_force;
  };
  constexpr int steps = 200;
  for (int i = 1; i <= steps; ++i) {
    const double s = end * i / steps;
    const std::optional<bool> b = below(s);
    if (!b) return end * (i - 1) / steps;  // the law cannot be followed further
    if (!*b) return numerics::bisect(below, end * (i - 1) / steps, s, {}).x;
  }
  return end;
}

}  // namespace

double comfort_stretch(const FittedFabric& fabric, const std::string& direction) {
  const auto dir = db::parse_direction(direction);
  for (const auto& d : fabric.shell.directions)
    if (d.direction == direction && dir) return comfort_end(fabric.params.inplane, db::pull_angle(*dir), d.fitted_max_stretch);
  return 0.0;
}

Eigen::Matrix2d law_stress(const shell::InplaneMaterial& law, const Eigen::Matrix2d& G) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(2.0 * G + Eigen::Matrix2d::Identity());
  const Eigen::Matrix2d F = eig.operatorSqrt();
  return F.inverse() * law.pk1(F);
}

double fitted_range_end(const FittedFabric& fabric, double angle) {
  std::vector<std::pair<double, double>> ends;  // (angle, fitted range's end), by angle
  for (const auto& d : fabric.shell.directions)
    if (const auto dir = db::parse_direction(d.direction)) ends.emplace_back(db::pull_angle(*dir), d.fitted_max_stretch);
  std::sort(ends.begin(), ends.end());
  if (ends.empty()) return 0.0;
  if (angle <= ends.front().first) return ends.front().second;
  for (std::size_t i = 1; i < ends.size(); ++i)
    if (angle <= ends[i].first) {
      const double t = (angle - ends[i - 1].first) / (ends[i].first - ends[i - 1].first);
      return (1.0 - t) * ends[i - 1].second + t * ends[i].second;
    }
  return ends.back().second;
}

double comfort_stretch_at(const FittedFabric& fabric, double angle) {
  return comfort_end(fabric.params.inplane, angle, fitted_range_end(fabric, angle));
}

}  // namespace yarnfit::exports
