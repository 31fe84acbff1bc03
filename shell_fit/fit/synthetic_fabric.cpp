#include "shell_fit/fit/synthetic_fabric.hpp"

#include <random>
#include <sstream>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"

namespace yarnfit::shell {

namespace fs = std::filesystem;
using db::format_g;

void write_synthetic_shell_fabric(const SyntheticShellOptions& o, const fs::path& folder, bool overwrite) {
  if (fs::exists(folder / "fabric.yaml") && !overwrite)
    throw std::runtime_error((folder / "fabric.yaml").string() + ": exists; pass --force to replace it");
  fs::create_directories(folder);
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);

  std::ostringstream tests;
  for (const auto& [dir, s_max] : o.max_stretch) {
    ClampedStretchSetup setup;
    setup.length = o.length;
    setup.width = o.width;
    setup.material_angle = -db::pull_angle(dir);
    setup.gauge_length = o.gauge_length;
    setup.gauge_width = o.gauge_width;
    setup.target_edge = o.target_edge;
    setup.refinements = o.refinements;
    std::vector<double> targets;
    for (int i = 1; i < o.points; ++i) targets.push_back(s_max * i / (o.points - 1));
    const auto run = ClampedStretchScene(setup).run(o.params.inplane, targets);
    if (!run.ok) throw std::runtime_error("synthetic " + std::string(db::to_string(dir)) + " test: " + run.message);
    std::ostringstream csv;
    csv << "# simulated by yarnfit synth shell from the ground_truth parameters"
        << (o.noise > 0 ? " with " + format_g(100 * o.noise) + " % noise" : std::string()) << "\n";
    csv << "stretch,force_N,compression\n0,0,0\n";
    for (const auto& smp : run.samples) {
      const double f = smp.force * (1.0 + o.noise * gauss(rng));
      const double c = smp.compression * (1.0 + o.noise * gauss(rng));
      csv << format_g(smp.measured_stretch, 12) << "," << format_g(std::max(f, 0.0), 12) << "," << format_g(c, 12) << "\n";
    }
    const std::string name = "stretch_" + std::string(db::to_string(dir)) + ".csv";
    db::write_text_file_atomically(folder / name, csv.str());
    tests << "  " << db::to_string(dir) << ": {file: " << name << "}\n";
  }
  const auto& p = o.params.inplane;
  std::ostringstream yaml;
  yaml << "# Synthetic fabric written by yarnfit synth shell: curves simulated from ground_truth.\n"
       << "id: " << o.id << "\nfamily: " << o.family << "\n"
       << "description: \"Simulated clamped stretch tests (mesh " << format_g(o.target_edge * 1e3) << " mm, "
       << o.refinements << " refinements, noise " << format_g(100 * o.noise) << " %)\"\n"
       << "yarns:\n  - material: synthetic\n    denier: 100\n    mass_fraction: 1.0\n"
       << "swatch: {length_mm: " << format_g(o.length * 1e3, 10) << ", width_mm: " << format_g(o.width * 1e3, 10) << "}\n"
       << "stretch_tests:\n";
  std::string text = yaml.str() + tests.str();
  if (o.gauge_length || o.gauge_width) {
    // Every test carries the gauge: rewrite each line with it.
    std::string gauge = ", gauge: {";
    if (o.gauge_length) gauge += "length_mm: " + format_g(*o.gauge_length * 1e3, 10);
    if (o.gauge_length && o.gauge_width) gauge += ", ";
    if (o.gauge_width) gauge += "width_mm: " + format_g(*o.gauge_width * 1e3, 10);
    gauge += "}}";
    std::string out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("  ", 0) == 0 && line.find("{file: stretch_") != std::string::npos) line.replace(line.size() - 1, 1, gauge);
      out += line + "\n";
    }
    text = out;
  }
  text += "ground_truth: {kxx: " + format_g(p.kxx, 12) + ", kxy: " + format_g(p.kxy, 12) + ", kyy: " +
          format_g(p.kyy, 12) + ", kss: " + format_g(p.kss, 12) + ", kn1: " + format_g(p.kn1, 12) +
          ", kn2: " + format_g(p.kn2, 12) + "}\n";
  db::write_text_file_atomically(folder / "fabric.yaml", text);
}

}  // namespace yarnfit::shell
