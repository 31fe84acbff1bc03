#include "yarn_fit/fit/synth/synthetic_yarn_fabric.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace yarnfit::yarn {

namespace fs = std::filesystem;
using db::format_g;

SyntheticYarnResult simulate_yarn_targets(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                          const SyntheticYarnOptions& options) {
  const auto start = numerics::Clock::now();
  if (options.directions.empty()) throw Error(ErrorCategory::input, "synth yarn: no direction given");
  if (!(options.max_stretch > 0.0) || !std::isfinite(options.max_stretch)) {
    throw Error(ErrorCategory::input, "synth yarn: max stretch must be positive and finite");
  }
  if (options.points < 2) throw Error(ErrorCategory::input, "synth yarn: at least 2 points per direction");
  if (const db::Problems invalid = params.problems(); !invalid.empty())
    throw Error(ErrorCategory::input, "synth yarn: parameters: " + invalid.one_line());

  SyntheticYarnResult out;
  yarn::YarnSystem system(yarn::make_yarn_tile(tile), params);
  Eigen::VectorXd g_rest = Eigen::VectorXd::Zero(system.dof_count());
  out.rest = yarn::relax_rest_shape(system, g_rest, options.rest);
  if (!out.rest.converged) {
    throw Error(ErrorCategory::solve,
                "synth yarn: rest-shape heuristic did not converge: " + out.rest.last_solve.message);
  }
  const std::vector<double> stretches = yarn::even_stretches(options.max_stretch, options.points);
  // Targets are ground truth: every solve to the force tolerance. With the stress read-out test
  // (the solver's default) the toe truth's own targets scored g = 2.7e-4 against 7.9e-5.
  yarn::StretchSweepOptions sweep_options;
  sweep_options.solve.stress_tolerance = 0.0;
  for (const db::Direction dir : options.directions) {
    Eigen::VectorXd g = g_rest;
    const yarn::StretchSweep sweep = yarn::sweep_stretch(system, db::pull_angle(dir), stretches, g, sweep_options);
    db::DirectionTargets t;
    t.direction = dir;
    for (const auto& p : sweep.points) {
      if (!p.ok) {
        throw Error(ErrorCategory::solve, "synth yarn: " + std::string(db::to_string(dir)) + " stretch " +
                                 format_g(p.chi.stretch) + " failed: " + p.message);
      }
      t.stretch.push_back({p.chi.stretch, p.chi.compression, p.stress_s, true});
    }
    out.targets.push_back(std::move(t));
  }
  out.seconds = numerics::seconds_since(start);
  return out;
}

namespace {

std::string fabric_yaml(const yarn::YarnParams& p, const SyntheticYarnOptions& o) {
  std::ostringstream y;
  y << "# Synthetic fabric made by `yarnfit synth yarn`: uniform yarn-level responses of the tile\n"
       "# after the rest-shape heuristic with the parameters under ground_truth (SI units).\n"
    << "id: " << o.id << "\n"
    << "family: " << o.family << "\n"
    << "description: \"Synthetic: stretch curves are the uniform periodic-tile response (force = line stress x "
       "width) from known yarn parameters. Not a measurement.\"\n"
    << "yarns:\n"
    << "  - material: synthetic\n"
    << "    denier: 150\n"
    << "    mass_fraction: 1.0\n"
    << "    stiffness_N: " << format_g(p.ks2, 17) << "\n"
    << "pattern:\n  file: tile.pyp\n  weft_axis: x\n"
    << "swatch: {length_mm: " << format_g(o.swatch_length * 1e3, 12) << ", width_mm: "
    << format_g(o.swatch_width * 1e3, 12) << "}\n"
    << "stretch_tests:\n";
  for (const auto d : o.directions) {
    y << "  " << db::to_string(d) << ": {file: stretch_" << db::to_string(d) << ".csv}\n";
  }
  y << "ground_truth: " << yarn::to_json(p).dump() << "\n";  // JSON flow mapping is YAML
  return y.str();
}

std::string stretch_csv(const db::DirectionTargets& t, double width) {
  std::ostringstream c;
  c << "# uniform " << db::to_string(t.direction) << " response of the yarn tile (yarnfit synth yarn)\n"
    << "stretch,force_N,compression\n";
  for (const auto& p : t.stretch) {
    // The rest state carries a residual stress of the order of 1e-3 of the curve; a clamp
    // force is never negative.
    c << format_g(p.stretch, 12) << "," << format_g(std::max(0.0, p.stress * width), 12) << ","
      << format_g(p.compression, 12) << "\n";
  }
  return c.str();
}

}  // namespace

SyntheticYarnResult write_synthetic_yarn_fabric(const db::PeriodicTile& tile, const yarn::YarnParams& params,
                                                const SyntheticYarnOptions& options, const fs::path& out,
                                                bool overwrite) {
  const fs::path folder = out / "fabric";
  if (!overwrite && fs::exists(folder / "fabric.yaml")) {
    throw Error(ErrorCategory::conflict, (folder / "fabric.yaml").string() + " exists (use --force to replace it)");
  }
  SyntheticYarnResult r = simulate_yarn_targets(tile, params, options);
  fs::create_directories(folder);
  db::write_uniform_targets_csv(r.targets, out / "uniform_targets.csv");
  db::write_pyp(tile, folder / "tile.pyp", 17);
  for (const auto& t : r.targets) {
    db::write_text_file_atomically(folder / ("stretch_" + std::string(db::to_string(t.direction)) + ".csv"),
                                   stretch_csv(t, options.swatch_width));
  }
  db::write_text_file_atomically(folder / "fabric.yaml", fabric_yaml(params, options));
  return r;
}

}  // namespace yarnfit::yarn
