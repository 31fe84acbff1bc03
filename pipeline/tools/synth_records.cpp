#include "pipeline/tools/synth_records.hpp"

#include <cmath>
#include <filesystem>
#include <optional>
#include <utility>

#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "pipeline/synthetic_fabric.hpp"
#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::pipeline {
namespace {

using db::format_g;

// The tile and the parameters, or their problems.
std::optional<std::pair<db::PeriodicTile, yarn::YarnParams>> read_model(const KnownYarnModel& m, db::Problems& problems) {
  if (!(std::isfinite(m.ks2) && m.ks2 >= 0.0)) problems.add_field("ks2", "must be a positive stiffness [N]");
  const auto tile = db::read_pyp(m.pattern, problems);
  std::optional<yarn::ParameterScales> scales;
  if (tile && m.ks2 > 0.0) scales = yarn::scales_of(*tile, m.ks2);
  const auto params = yarn::read_yarn_params(m.params_file, scales, problems);
  if (!tile || !params) return std::nullopt;
  return std::make_pair(*tile, *params);
}

// Named directions; "none" stands for no direction.
std::vector<db::Direction> directions_of(const std::vector<std::string>& names, const std::string& field,
                                         db::Problems& problems) {
  std::vector<db::Direction> out;
  for (const auto& name : names) {
    if (name == "none") continue;
    if (const auto dir = db::parse_direction(name)) out.push_back(*dir);
    else problems.add_field(field, name + ": not a direction (weft, bias, warp)");
  }
  return out;
}

}  // namespace

std::string synth_shell(const SynthShellRequest& r, db::Problems& problems) {
  const bool any_ktheta = r.values.ktheta_weft > 0 || r.values.ktheta_bias > 0 || r.values.ktheta_warp > 0;
  const bool with_bending = any_ktheta && !r.bending.empty();
  problems.append(scene_problems(r.values, with_bending));
  shell::SyntheticShellOptions o = synthetic_options(r.values);
  o.id = r.id;
  o.family = r.family;
  o.max_stretch.clear();
  if (r.weft > 0) o.max_stretch[db::Direction::weft] = r.weft;
  if (r.bias > 0) o.max_stretch[db::Direction::bias] = r.bias;
  if (r.warp > 0) o.max_stretch[db::Direction::warp] = r.warp;
  if (o.max_stretch.empty()) problems.add_field("stretches", "at least one direction needs a positive stretch");
  if (with_bending) o.bending_directions = directions_of(r.bending, "bending", problems);
  if (!problems.empty()) return {};
  o.noise = r.noise;
  o.seed = r.seed;
  o.points = r.points;
  o.bending_points = r.bend_points;
  shell::write_synthetic_shell_fabric(o, r.out, r.force);
  return "wrote synthetic fabric " + r.id + " to " + r.out + "\n";
}

std::string synth_yarn(const SynthYarnRequest& r, db::Problems& problems) {
  yarn::SyntheticYarnOptions o;
  o.id = r.id;
  o.family = r.family;
  o.max_stretch = r.max_stretch;
  o.points = r.points;
  o.directions = directions_of(r.directions, "directions", problems);
  const auto model = read_model(r.model, problems);
  if (!problems.empty() || !model) return {};
  const auto made = yarn::write_synthetic_yarn_fabric(model->first, model->second, o, r.out, r.force);
  const std::filesystem::path out(r.out);
  return "wrote " + (out / "uniform_targets.csv").string() + " and fabric " + r.id + " in " + (out / "fabric").string() +
         " (" + format_g(made.seconds, 3) + " s)\n";
}

std::string synth_fabric(const SynthFabricRequest& r, db::Problems& problems) {
  SyntheticFabricOptions o;
  o.id = r.id;
  o.family = r.family;
  o.max_stretch = r.max_stretch;
  o.max_curvature = r.max_curvature;
  o.areal_density = r.density_gsm * 1e-3;
  o.stretch_directions = directions_of(r.directions, "directions", problems);
  o.bending_directions = directions_of(r.bending, "bending", problems);
  if (const auto shell_model = shell::parse_inplane_model(r.shell_model)) o.model = *shell_model;
  else problems.add_field("shell_model", r.shell_model + ": not a shell model (stiffening or thesis)");
  const auto model = read_model(r.model, problems);
  if (!problems.empty() || !model) return {};
  const auto made = write_synthetic_fabric(model->first, model->second, o, r.out, r.force);
  return "wrote fabric " + r.id + " in " + r.out + " (" + format_g(made.seconds, 3) +
         " s); its law reproduces the yarn model's samples to " + format_g(made.law.stress_misfit_pct, 2) +
         " % (stress), " + format_g(made.law.compression_misfit_pct, 2) + " % (compression), " +
         format_g(made.law.bending_misfit_pct, 2) + " % (bending)\n";
}

}  // namespace yarnfit::pipeline
