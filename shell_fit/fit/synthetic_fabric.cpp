#include "shell_fit/fit/synthetic_fabric.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/fit/bending_fit.hpp"

namespace yarnfit::shell {

namespace fs = std::filesystem;
using db::format_g;

namespace {

// 1 + noise·N(0, 1), or exactly 1 without noise (no draw, so noise-free output does not
// depend on the generator).
double noise_factor(double noise, std::mt19937* rng) {
  if (!(noise > 0.0) || rng == nullptr) return 1.0;
  std::normal_distribution<double> gauss(0.0, 1.0);
  return 1.0 + noise * gauss(*rng);
}

std::string comment_line(const std::string& comment) { return comment.empty() ? std::string() : "# " + comment + "\n"; }

}  // namespace

ClampedStretchSetup synthetic_stretch_setup(const SyntheticShellOptions& o, db::Direction direction) {
  ClampedStretchSetup setup;
  setup.length = o.length;
  setup.width = o.width;
  setup.material_angle = -db::pull_angle(direction);
  setup.gauge_length = o.gauge_length;
  setup.gauge_width = o.gauge_width;
  setup.target_edge = o.target_edge;
  setup.refinements = o.refinements;
  return setup;
}

PearLoopSetup synthetic_bending_setup(const SyntheticShellOptions& o, db::Direction direction) {
  PearLoopSetup setup;
  setup.length = o.length;
  setup.width = o.width;
  setup.material_angle = -db::pull_angle(direction);
  setup.areal_density = o.areal_density;
  setup.target_edge = o.bending_target_edge;
  setup.refinements = o.bending_refinements;
  return setup;
}

std::string simulate_stretch_csv(const InplaneParams& params, const ClampedStretchSetup& setup, double max_stretch,
                                 int points, const std::string& comment, int digits, double noise, std::mt19937* rng) {
  if (points < 2 || !(max_stretch > 0.0))
    throw Error(ErrorCategory::input, "a stretch curve needs 2 points and a positive largest stretch");
  std::vector<double> targets;
  for (int i = 1; i < points; ++i) targets.push_back(max_stretch * i / (points - 1));
  const auto run = ClampedStretchScene(setup).run(params, targets);
  if (!run.ok) throw Error(ErrorCategory::solve, run.message);
  std::ostringstream csv;
  csv << comment_line(comment) << "stretch,force_N,compression\n0,0,0\n";
  for (const auto& smp : run.samples) {
    const double f = smp.force * noise_factor(noise, rng);
    const double c = smp.compression * noise_factor(noise, rng);
    csv << format_g(smp.measured_stretch, digits) << "," << format_g(std::max(f, 0.0), digits) << ","
        << format_g(c, digits) << "\n";
  }
  return csv.str();
}

std::vector<double> synthetic_clamp_distances(int points) {
  std::vector<double> d;
  for (int i = 0; i < points; ++i)
    d.push_back(points == 1 ? k_bending_min_distance
                            : k_bending_min_distance + (k_bending_max_distance - k_bending_min_distance) * i / (points - 1));
  return d;
}

std::string simulate_bending_csv(const ShellParams& params, const PearLoopSetup& setup,
                                 const std::vector<double>& clamp_distances, const std::string& comment, int digits,
                                 double noise, std::mt19937* rng) {
  for (double k : params.bending.ktheta)
    if (!(k > 0.0 && std::isfinite(k))) throw Error(ErrorCategory::input, "a pear-loop test needs positive k_theta (weft, bias, warp)");
  const auto run = PearLoopScene(setup).run(params, clamp_distances);
  if (!run.ok) throw Error(ErrorCategory::solve, run.message);
  std::ostringstream csv;
  csv << comment_line(comment) << "clamp_distance_mm,aspect_ratio,height_mm,width_mm\n";
  for (const auto& smp : run.samples) {
    const double r = smp.aspect_ratio * noise_factor(noise, rng);
    csv << format_g(smp.clamp_distance * 1e3, digits) << "," << format_g(r, digits) << ","
        << format_g(smp.height * 1e3, digits) << "," << format_g(smp.width * 1e3, digits) << "\n";
  }
  return csv.str();
}

namespace {

// fabric.yaml with every stretch test's line carrying the gauge the options give.
std::string with_gauge(const std::string& yaml, const SyntheticShellOptions& o) {
  std::string gauge = ", gauge: {";
  if (o.gauge_length) gauge += "length_mm: " + format_g(*o.gauge_length * 1e3, 10);
  if (o.gauge_length && o.gauge_width) gauge += ", ";
  if (o.gauge_width) gauge += "width_mm: " + format_g(*o.gauge_width * 1e3, 10);
  gauge += "}}";
  std::string out;
  std::istringstream in(yaml);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  ", 0) == 0 && line.find("{file: stretch_") != std::string::npos) line.replace(line.size() - 1, 1, gauge);
    out += line + "\n";
  }
  return out;
}

// The synthetic fabric's fabric.yaml: what made it, its tests (`tests` and `bending`: the lines
// under stretch_tests and bending_tests) and the ground truth.
std::string synthetic_fabric_yaml(const SyntheticShellOptions& o, const std::string& tests, const std::string& bending) {
  const auto& p = o.params.inplane;
  std::ostringstream yaml;
  yaml << "# Synthetic fabric written by yarnfit synth shell: curves simulated from ground_truth.\n"
       << "id: " << o.id << "\nfamily: " << o.family << "\n"
       << "description: \"Simulated clamped stretch " << (o.bending_directions.empty() ? "" : "and pear-loop ")
       << "tests (mesh " << format_g(o.target_edge * 1e3) << " mm, " << o.refinements << " refinements"
       << (o.bending_directions.empty() ? std::string()
                                        : ", pear loop " + format_g(o.bending_target_edge * 1e3) + " mm, " +
                                              std::to_string(o.bending_refinements) + " refinements")
       << ", noise " << format_g(100 * o.noise) << " %)\"\n";
  if (!o.bending_directions.empty()) yaml << "areal_density_gsm: " << format_g(o.areal_density * 1e3, 10) << "\n";
  yaml << "yarns:\n  - material: synthetic\n    denier: 100\n    mass_fraction: 1.0\n"
       << "swatch: {length_mm: " << format_g(o.length * 1e3, 10) << ", width_mm: " << format_g(o.width * 1e3, 10) << "}\n"
       << "stretch_tests:\n";
  std::string text = yaml.str() + tests;
  if (o.gauge_length || o.gauge_width) text = with_gauge(text, o);
  if (!o.bending_directions.empty()) text += "bending_tests:\n" + bending;
  text += "ground_truth: {kxx: " + format_g(p.kxx, 12) + ", kxy: " + format_g(p.kxy, 12) + ", kyy: " +
          format_g(p.kyy, 12) + ", kss: " + format_g(p.kss, 12) + ", kn1: " + format_g(p.kn1, 12) +
          ", kn2: " + format_g(p.kn2, 12);
  if (!o.bending_directions.empty()) {
    const auto& k = o.params.bending.ktheta;
    text += ", ktheta_weft: " + format_g(k[0], 12) + ", ktheta_bias: " + format_g(k[1], 12) +
            ", ktheta_warp: " + format_g(k[2], 12);
  }
  text += "}\n";
  return text;
}

}  // namespace

void write_synthetic_shell_fabric(const SyntheticShellOptions& o, const fs::path& folder, bool overwrite) {
  if (fs::exists(folder / "fabric.yaml") && !overwrite)
    throw Error(ErrorCategory::conflict, (folder / "fabric.yaml").string() + ": exists; pass --force to replace it");
  if (!o.bending_directions.empty()) {
    for (double k : o.params.bending.ktheta)
      if (!(k > 0.0 && std::isfinite(k)))
        throw Error(ErrorCategory::input, "bending tests need positive k_theta for weft, bias and warp");
    if (!(o.areal_density > 0.0 && std::isfinite(o.areal_density)))
      throw Error(ErrorCategory::input, "bending tests need a positive areal density");
  }
  fs::create_directories(folder);
  std::mt19937 rng(o.seed);
  const std::string noise_note = o.noise > 0 ? " with " + format_g(100 * o.noise) + " % noise" : std::string();

  std::ostringstream tests;
  for (const auto& [dir, s_max] : o.max_stretch) {
    std::string csv;
    try {
      csv = simulate_stretch_csv(o.params.inplane, synthetic_stretch_setup(o, dir), s_max, o.points,
                                 "simulated by yarnfit synth shell from the ground_truth parameters" + noise_note, 12,
                                 o.noise, &rng);
    } catch (const Error& e) {
      throw with_context("synthetic " + std::string(db::to_string(dir)) + " test: ", e);
    }
    const std::string name = "stretch_" + std::string(db::to_string(dir)) + ".csv";
    db::write_text_file_atomically(folder / name, csv);
    tests << "  " << db::to_string(dir) << ": {file: " << name << "}\n";
  }
  std::ostringstream bending;
  for (const db::Direction dir : o.bending_directions) {
    std::string csv;
    try {
      csv = simulate_bending_csv(o.params, synthetic_bending_setup(o, dir), synthetic_clamp_distances(o.bending_points),
                                 "pear loop simulated by yarnfit synth shell from the ground_truth parameters" + noise_note,
                                 12, o.noise, &rng);
    } catch (const Error& e) {
      throw with_context("synthetic " + std::string(db::to_string(dir)) + " bending test: ", e);
    }
    const std::string name = "bend_" + std::string(db::to_string(dir)) + ".csv";
    db::write_text_file_atomically(folder / name, csv);
    bending << "  " << db::to_string(dir) << ": {file: " << name << "}\n";
  }

  db::write_text_file_atomically(folder / "fabric.yaml", synthetic_fabric_yaml(o, tests.str(), bending.str()));
}

}  // namespace yarnfit::shell
