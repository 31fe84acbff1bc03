#include "pipeline/synthetic_fabric.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "numerics/util/error.hpp"
#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::pipeline {

namespace fs = std::filesystem;
using db::format_g;

namespace {

// The gauge marks of a gauged stretch test (the bundled examples' warp tests).
constexpr double k_gauge_length = 0.080, k_gauge_width = 0.040;

// Δσ_κ(κ) = σ_κ(κ) − σ_κ(0) of the relaxed tile bent about each direction, at `points`
// curvatures evenly up to κ_max (the yarn fit's bending check reads the same).
void add_bending_samples(const db::PeriodicTile& tile, const yarn::YarnParams& params, const SyntheticFabricOptions& o,
                         std::vector<db::DirectionTargets>& samples) {
  yarn::YarnSystem system(yarn::make_yarn_tile(tile), params);
  Eigen::VectorXd g_rest = Eigen::VectorXd::Zero(system.dof_count());
  if (!yarn::relax_rest_shape(system, g_rest).converged)
    throw Error(ErrorCategory::solve, "synth fabric: the rest shape did not converge");
  yarn::EquilibriumOptions solve;
  solve.stress_tolerance = 0.0;  // ground truth: every solve to the force tolerance
  for (const db::Direction dir : o.bending_directions) {
    yarn::YarnSystem bent = system;
    Eigen::VectorXd g = g_rest;
    yarn::CoarseDeformation chi;
    chi.angle = db::pull_angle(dir);
    const yarn::BendingSample flat = yarn::simulate_bending(bent, chi, g, 0.0, solve);
    if (!flat.ok) throw Error(ErrorCategory::solve, "synth fabric: " + std::string(db::to_string(dir)) + " bending at 0: " + flat.message);
    db::DirectionTargets* t = nullptr;
    for (auto& s : samples)
      if (s.direction == dir) t = &s;
    if (t == nullptr) {
      samples.push_back({dir, {}, {}});
      t = &samples.back();
    }
    t->bending.push_back({0.0, 0.0});
    for (int j = 1; j <= o.curvature_points; ++j) {
      chi.curvature = o.max_curvature * j / o.curvature_points;
      const yarn::BendingSample b = yarn::simulate_bending(bent, chi, g, 0.0, solve);
      if (!b.ok)
        throw Error(ErrorCategory::solve, "synth fabric: " + std::string(db::to_string(dir)) + " bending at " +
                                 format_g(chi.curvature) + " 1/m: " + b.message);
      t->bending.push_back({chi.curvature, b.stress_kappa - flat.stress_kappa});
    }
  }
}

std::string shell_truth(const shell::ShellParams& law, shell::InplaneModel model, int digits) {
  const auto v = shell::to_array(law.inplane);
  const int n = model == shell::InplaneModel::stiffening ? shell::k_inplane_param_count : shell::k_first_lockup_param;
  std::string out;
  for (int k = 0; k < n; ++k) out += std::string(", ") + shell::k_inplane_param_names[k] + ": " + format_g(v[static_cast<std::size_t>(k)], digits);
  const char* const names[3] = {"ktheta_weft", "ktheta_bias", "ktheta_warp"};
  for (std::size_t k = 0; k < 3; ++k) out += std::string(", ") + names[k] + ": " + format_g(law.bending.ktheta[k], digits);
  return out;
}

}  // namespace

SyntheticFabricResult write_synthetic_fabric(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                             const SyntheticFabricOptions& o, const fs::path& folder, bool overwrite) {
  const auto start = numerics::Clock::now();
  if (fs::exists(folder / "fabric.yaml") && !overwrite)
    throw Error(ErrorCategory::conflict, (folder / "fabric.yaml").string() + ": exists; pass --force to replace it");
  if (o.stretch_directions.empty()) throw Error(ErrorCategory::input, "synth fabric: no stretch direction");
  if (!(o.max_curvature > 0.0) || o.curvature_points < 2)
    throw Error(ErrorCategory::input, "synth fabric: the bending samples need a positive largest curvature and 2 points");
  if (!(o.areal_density > 0.0)) throw Error(ErrorCategory::input, "synth fabric: the areal density must be positive");
  SyntheticFabricResult out;
  // 1. The yarn model's uniform responses.
  yarn::SyntheticYarnOptions yo;
  yo.directions = o.stretch_directions;
  yo.max_stretch = o.max_stretch;
  yo.points = o.uniform_points;
  out.samples = yarn::simulate_yarn_targets(tile, params, yo).targets;
  if (!o.bending_directions.empty()) add_bending_samples(tile, params, o, out.samples);
  // 2. Homogenised to the shell law.
  out.law = shell::fit_law_to_samples(out.samples, o.model);
  if (!out.law.ok) throw Error(ErrorCategory::solve, "synth fabric: no shell law reproduces the yarn model: " + out.law.message);
  // 3. The record's tests with that law.
  shell::SyntheticShellOptions so;
  so.params = out.law.params;
  so.points = o.test_points;
  so.bending_directions = o.bending_directions;
  so.areal_density = o.areal_density;
  fs::create_directories(folder);
  std::ostringstream tests, bending;
  for (const db::Direction dir : o.stretch_directions) {
    const std::string name = "stretch_" + std::string(db::to_string(dir)) + ".csv";
    shell::ClampedStretchSetup setup = shell::synthetic_stretch_setup(so, dir);
    const bool gauged = std::find(o.gauged_directions.begin(), o.gauged_directions.end(), dir) != o.gauged_directions.end();
    if (gauged) setup.gauge_length = k_gauge_length, setup.gauge_width = k_gauge_width;
    const std::string csv = shell::simulate_stretch_csv(out.law.params.inplane, setup, o.max_stretch, o.test_points,
                                                        "simulated by yarnfit synth fabric: the yarn model's law", o.digits);
    db::write_text_file_atomically(folder / name, csv);
    if (gauged)
      tests << "  " << db::to_string(dir) << ":\n    file: " << name << "\n    gauge: {length_mm: " << format_g(1e3 * k_gauge_length)
            << ", width_mm: " << format_g(1e3 * k_gauge_width) << "}\n";
    else
      tests << "  " << db::to_string(dir) << ": {file: " << name << "}\n";
  }
  for (const db::Direction dir : o.bending_directions) {
    const std::string name = "bend_" + std::string(db::to_string(dir)) + ".csv";
    const std::string csv = shell::simulate_bending_csv(out.law.params, shell::synthetic_bending_setup(so, dir),
                                                        shell::synthetic_clamp_distances(so.bending_points),
                                                        "pear loop simulated by yarnfit synth fabric: the yarn model's law", o.digits);
    db::write_text_file_atomically(folder / name, csv);
    bending << "  " << db::to_string(dir) << ": {file: " << name << "}\n";
  }
  db::write_pyp(tile, folder / "tile.pyp", 17);
  const int d = o.digits;
  std::ostringstream yaml;
  yaml << (o.header.empty() ? "# Synthetic fabric written by yarnfit synth fabric: the tests come from the yarn model under\n"
                              "# ground_truth (its uniform responses homogenised to a shell law, whose parameters are there too).\n"
                            : o.header)
       << "id: " << o.id << "\nfamily: " << o.family << "\n"
       << "description: \""
       << (o.description.empty() ? "Synthetic: clamped stretch and pear-loop tests simulated from a known yarn model "
                                   "(its homogenised shell law). Not a measurement."
                                 : o.description)
       << "\"\n";
  if (!o.bending_directions.empty()) yaml << "areal_density_gsm: " << format_g(o.areal_density * 1e3, 10) << "\n";
  yaml << "yarns:\n  - material: " << o.yarn_material << "\n    denier: " << o.denier << "\n";
  if (o.filaments > 0) yaml << "    filaments: " << o.filaments << "\n";
  yaml << "    mass_fraction: 1.0\n    stiffness_N: " << format_g(params.ks2, d) << "\n"
       << "pattern: {file: tile.pyp, weft_axis: x}\n"
       << "swatch: {length_mm: " << format_g(so.length * 1e3, 10) << ", width_mm: " << format_g(so.width * 1e3, 10) << "}\n"
       << "stretch_tests:\n"
       << tests.str();
  if (!o.bending_directions.empty()) yaml << "bending_tests:\n" << bending.str();
  yaml << "ground_truth: {ks1: " << format_g(params.ks1, d) << ", eps_s: " << format_g(params.eps_s, d)
       << ", kb: " << format_g(params.kb, d) << ", R1: " << format_g(params.r1, d) << ", kc1: " << format_g(params.kc1, d)
       << ", ks2: " << format_g(params.ks2, d) << ", kc2: " << format_g(params.kc2, d) << ", R2: " << format_g(params.r2, d)
       << shell_truth(out.law.params, o.model, d) << "}\n";
  db::write_text_file_atomically(folder / "fabric.yaml", yaml.str());
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::pipeline
