#include "pipeline/tools/simulate_yarn.hpp"

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"
#include "yarn_fit/scenes/sample_json.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace yarnfit::pipeline {
namespace {

namespace fs = std::filesystem;
using db::format_g;
using nlohmann::json;
using numerics::Clock;

yarn::YarnSceneSetup scene_setup(const YarnSceneRequest& r) {
  yarn::YarnSceneSetup s = r.setup;
  s.compression = r.compression_method == "cobyla" ? yarn::CompressionMethod::cobyla : yarn::CompressionMethod::root_find;
  return s;
}

// Reads the pattern and the parameters; empty with `problems` when something is wrong.
std::optional<yarn::YarnScene> load_scene(const YarnSceneRequest& r, db::Problems& problems) {
  const std::size_t before = problems.size();
  if (!(std::isfinite(r.setup.ks2) && r.setup.ks2 >= 0.0))
    problems.add_field("ks2", format_g(r.setup.ks2) + ": must be a positive stiffness [N]");
  const double tolerance = r.setup.stress_tolerance;
  if (!(std::isfinite(tolerance) && (tolerance >= 0.0 || tolerance == yarn::EquilibriumOptions{}.stress_tolerance)))
    problems.add_field("stress_tolerance", format_g(tolerance) + ": must be a stress ≥ 0 [N/m]");
  if (r.compression_method != "root" && r.compression_method != "cobyla")
    problems.add_field("compression_method", r.compression_method + ": not a method (root or cobyla)");
  if (!(r.threads >= 1)) problems.add_field("threads", "must be at least 1");
  db::Problems found;
  auto scene = yarn::load_yarn_scene(scene_setup(r), found);
  bool fixed_missing = false;
  for (const auto& p : found.items())
    fixed_missing = fixed_missing || ((p.field == "ks2" || p.field == "kc2" || p.field == "R2") && p.message == "missing");
  problems.append(found);
  if (fixed_missing && !(r.setup.ks2 > 0.0))
    problems.add_field("ks2", "not given: write ks2, kc2 and R2 in " + r.setup.params.string() +
                                  ", or pass --ks2 N to derive the missing ones from the tile");
  if (problems.size() != before) return std::nullopt;
  return scene;
}

// Places an output file (creating its folder) before anything is simulated; a problem of
// `field` when it is a folder or its folder cannot be made.
void place_output_file(const std::string& field, const std::string& file, const std::string& kind, db::Problems& problems) {
  std::error_code ec;
  if (fs::is_directory(file)) problems.add_field(field, file + ": is a folder; expected " + kind + " file name");
  else if (fs::path(file).has_parent_path()) fs::create_directories(fs::path(file).parent_path(), ec);
  if (ec) problems.add_field(field, file + ": cannot create its folder: " + ec.message());
}

// A stage with no steps (the rest shape, a solve).
void report_stage(const numerics::ProgressFn& progress, const std::string& stage, Clock::time_point start) {
  if (!progress) return;
  numerics::Progress p;
  p.stage = stage;
  p.step_name.clear();
  p.seconds = numerics::seconds_since(start);
  progress(p);
}

// Threads, then the rest shape.
void prepare(yarn::YarnScene& scene, const YarnSceneRequest& r, const numerics::ProgressFn& progress,
             Clock::time_point start) {
  omp_set_num_threads(r.threads);
  if (r.setup.rest_shape) report_stage(progress, "rest shape (" + std::to_string(r.setup.rest_rounds) + " rounds)", start);
  yarn::prepare_rest_state(scene, scene_setup(r));
}

// Writes an OBJ dump; the failure as `file: file: what`, empty when written.
std::string dump_obj(const std::string& file, const yarn::YarnScene& scene, const Eigen::VectorXd& g,
                     const yarn::CoarseDeformation& chi, bool neighbours, bool converged, const std::string& what) {
  try {
    yarn::write_tile_obj(*scene.system, g, chi, file, neighbours ? 3 : 1,
                         what + (converged ? ", equilibrium" : ", NOT converged: the start state under this deformation"));
    return {};
  } catch (const std::exception& e) {
    return file + ": file: " + e.what();
  }
}

std::string sample_summary(const YarnSimRequest& r, const yarn::YarnScene& scene, const yarn::SceneSample& sample,
                           const json& out, bool dumped) {
  const auto f = [](const json& v, int digits = 6) { return v.is_null() ? std::string("-") : format_g(v.get<double>(), digits); };
  std::ostringstream s;
  s << "yarn sim " << r.scene.setup.pattern.string() << ", " << r.scene.setup.direction << ": s = " << format_g(r.stretch)
    << ", c = " << f(out["compression"]) << (r.free_compression ? " (free)" : " (fixed)")
    << (r.curvature ? ", curvature " + format_g(*r.curvature) + " 1/m" : std::string()) << "\n"
    << "  " << (sample.ok ? sample.termination : "NOT converged (" + sample.termination + ")") << ", "
    << sample.newton_iterations << " Newton iterations in " << sample.solves << " solve(s), "
    << format_g(sample.seconds, 3) << " s\n"
    << "  energy density " << f(out["energy_density"]) << " J/m^2, stress_s " << f(out["stress_s"])
    << " N/m, orthogonal stress " << f(out["stress_c"], 3) << " N/m\n";
  if (r.curvature) s << "  stress_kappa " << f(out["stress_kappa"]) << " N\n";
  if (scene.rest)
    s << "  rest shape: " << scene.rest->rounds << " rounds, " << format_g(scene.rest->seconds, 3)
      << " s, largest rest-length change " << format_g(100 * scene.rest->max_length_change, 3) << " %\n";
  if (!r.dump.empty() && dumped) s << "  wrote " << r.dump << "\n";
  return s.str();
}

std::string curve_summary(const YarnCurveRequest& r, const yarn::YarnScene& scene, const yarn::StretchSweep& sweep,
                          double total_seconds) {
  std::ostringstream s;
  s << "yarn curve " << r.scene.setup.pattern.string() << ", " << r.scene.setup.direction << ", s from 0 to " << format_g(r.max_stretch)
    << " with free compression: " << sweep.points.size() - static_cast<std::size_t>(sweep.failures) << " of "
    << sweep.points.size() << " points converged, " << sweep.newton_iterations << " Newton iterations, "
    << format_g(sweep.seconds, 3) << " s";
  if (scene.rest) s << " (rest shape " << format_g(scene.rest->seconds, 3) << " s before)";
  s << "\n  " << std::setw(9) << "stretch" << std::setw(13) << "compression" << std::setw(13) << "Psi [J/m2]"
    << std::setw(15) << "sigma_s [N/m]" << std::setw(12) << "iterations" << std::setw(9) << "seconds" << "\n";
  for (const auto& p : sweep.points) {
    const auto f = [&](double v) { return p.ok ? format_g(v, 5) : std::string("-"); };
    s << "  " << std::setw(9) << format_g(p.chi.stretch, 4) << std::setw(13) << f(p.chi.compression) << std::setw(13)
      << f(p.energy_density) << std::setw(15) << f(p.stress_s) << std::setw(12) << p.newton_iterations << std::setw(9)
      << format_g(p.seconds, 3);
    if (p.ok && p.flat)
      s << "  flat in c over [" << format_g(p.band_lower, 4) << ", " << format_g(p.band_upper, 4)
        << "]: c of smallest |c|";
    s << "\n";
  }
  s << "  wrote " << r.out << (r.dump_dir.empty() ? "" : " and OBJ states in " + r.dump_dir) << " ("
    << format_g(total_seconds, 3) << " s in all)\n";
  return s.str();
}

}  // namespace

YarnSimOutcome simulate_yarn_sample(const YarnSimRequest& r, db::Problems& problems, const numerics::ProgressFn& progress) {
  const auto start = Clock::now();
  if (!(std::isfinite(r.stretch) && r.stretch > -1.0))
    problems.add_field("stretch", format_g(r.stretch) + ": must be greater than -1 (s = l/l0 - 1)");
  if (!(std::isfinite(r.compression) && r.compression < 1.0))
    problems.add_field("compression", format_g(r.compression) + ": must be less than 1 (c = 1 - w/w0)");
  if (r.free_compression && r.compression != 0.0)
    problems.add_field("free_compression", "finds the compression; give it or a fixed --compression, not both");
  if (r.curvature && !std::isfinite(*r.curvature)) problems.add_field("curvature", "must be finite [1/m]");
  auto scene = load_scene(r.scene, problems);
  if (problems.empty() && !r.dump.empty()) place_output_file("dump", r.dump, "an OBJ", problems);
  if (!problems.empty() || !scene) return {};

  const yarn::SceneSampleRequest request{r.stretch, r.compression, r.free_compression, r.curvature.value_or(0.0),
                                         r.curvature.has_value()};
  prepare(*scene, r.scene, progress, start);
  report_stage(progress, "equilibrium", start);
  const yarn::SceneSample sample = yarn::simulate_scene_sample(*scene, request);
  YarnSimOutcome outcome;
  outcome.json = yarn::sample_json(*scene, request, sample, r.scene.threads, numerics::seconds_since(start));
  outcome.converged = sample.ok;
  outcome.failure = sample.message;
  if (!r.dump.empty())
    outcome.dump_failure = dump_obj(r.dump, *scene, sample.g, sample.state_chi(), r.dump_neighbours, sample.sample.ok,
                                    "yarn sim " + r.scene.setup.pattern.string() + " " + r.scene.setup.direction);
  outcome.summary = sample_summary(r, *scene, sample, outcome.json, outcome.dump_failure.empty());
  return outcome;
}

YarnCurveOutcome sweep_yarn_stretch(const YarnCurveRequest& r, db::Problems& problems, const numerics::ProgressFn& progress) {
  const auto start = Clock::now();
  if (!(std::isfinite(r.max_stretch) && r.max_stretch > 0.0))
    problems.add_field("max_stretch", format_g(r.max_stretch) + ": must be positive (the sweep runs from 0)");
  if (r.points < 2) problems.add_field("points", "must be at least 2");
  auto scene = load_scene(r.scene, problems);
  if (problems.empty()) {
    // Fail before the simulation, not after it, when the outputs cannot be placed.
    place_output_file("out", r.out, "a CSV", problems);
    std::error_code ec;
    if (!r.dump_dir.empty()) fs::create_directories(r.dump_dir, ec);
    if (ec) problems.add_field("dump_dir", r.dump_dir + ": cannot create: " + ec.message());
  }
  if (!problems.empty() || !scene) return {};

  prepare(*scene, r.scene, progress, start);
  const std::vector<double> stretches = yarn::even_stretches(r.max_stretch, r.points);
  const int width = static_cast<int>(std::to_string(r.points - 1).size());
  YarnCurveOutcome outcome;
  bool dumps_ok = true;
  const auto sweep_start = Clock::now();
  yarn::StretchSweepOptions options;
  options.compression = scene->compression;
  options.solve = scene->solve;
  options.on_point = [&](std::size_t i, const yarn::Sample& s, const Eigen::VectorXd& g) {
    if (!r.dump_dir.empty()) {
      char name[96];
      std::snprintf(name, sizeof name, "%s_%0*zu_s%.4f.obj", r.scene.setup.direction.c_str(), width, i, s.chi.stretch);
      const std::string failed =
          dump_obj((fs::path(r.dump_dir) / name).string(), *scene, g, s.chi, r.dump_neighbours, s.ok,
                   "yarn curve " + r.scene.setup.pattern.string() + " " + r.scene.setup.direction);
      if (!failed.empty()) outcome.failures.push_back(failed);
      dumps_ok = dumps_ok && failed.empty();
    }
    if (!s.ok) outcome.failures.push_back("s = " + format_g(s.chi.stretch) + ": not converged: " + s.message);
    if (!progress) return;
    numerics::Progress p;
    p.step_name = "point";
    p.step = static_cast<int>(i) + 1;
    p.steps = static_cast<int>(stretches.size());
    p.detail = "s = " + format_g(s.chi.stretch, 4);
    p.seconds = numerics::seconds_since(sweep_start);
    progress(p);
  };
  const yarn::StretchSweep sweep = yarn::sweep_stretch(*scene->system, scene->angle, stretches, scene->g, options);
  db::write_text_file_atomically(r.out, yarn::sweep_csv(r.scene.setup.direction, sweep));
  const bool rest_ok = !scene->rest || scene->rest->converged;
  if (!rest_ok)
    outcome.failures.push_back(std::string("rest shape not converged: ") + yarn::to_string(scene->rest->last_solve.status) + ": " +
                               scene->rest->last_solve.message);
  if (sweep.failures > 0)
    outcome.failures.push_back(std::to_string(sweep.failures) + " point(s) did not converge (converged=0 in the CSV)");
  outcome.ok = sweep.ok() && rest_ok && dumps_ok;
  outcome.summary = curve_summary(r, *scene, sweep, numerics::seconds_since(start));
  return outcome;
}

}  // namespace yarnfit::pipeline
