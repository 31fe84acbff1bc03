// Writes the bundled example database (examples/fabrics), made entirely by the project: three
// records in two families (single-jersey: stockinette_demo, stockinette_light; double-knit:
// interlock_demo), each DB/<id>/fabric.yaml, tile.pyp, stretch_<dir>.csv and, where the record
// has pear-loop tests, bend_<dir>.csv.
//
// The tiles are the project's own synthetic stockinette (fabrics_db/tile/synthetic_stockinette)
// at each record's yarn radius and spacing.
// The curves are simulated with the thin-shell model from the parameters written under
// ground_truth, by the library's synthetic-fabric writer (shell_fit/fit/synthetic_fabric):
//   * clamped stretch tests on the 10 × 6 cm swatch (the warp test of two records read at
//     gauge marks), 16 points each, on a mesh refined once from the fit's default
//     (5 mm cells subdivided to 2.5 mm), so a fit on its default mesh does not meet its own
//     discretisation;
//   * pear-loop tests at 7 clamp distances from 3 to 34 mm (the fit's targets) on 2 mm cells
//     (the bending fit uses 2.5 mm), from k_θ whose bending lengths (about 1.3–2 cm) are those
//     of light knits; a simulated loop hangs as the shell model makes it, so the aspect ratios
//     stay above the weightless elastica's, which no k_θ could go below.
// The parameters are knit-like and of the magnitudes `yarnfit shell fit` finds on the acrylic
// records (tens to hundreds of N/m; the weft compliant, the warp stiff, a soft shear, lateral
// contraction shared between kxy and the area terms), chosen inside the fit's search range so
// that a fit on the example recovers them. Values are written with 6 significant digits: a
// regeneration on another build reproduces the committed files byte for byte.
//
// Usage: yarnfit_make_example --all examples/fabrics   (regenerates the bundled database)
//        yarnfit_make_example FOLDER [ID]               (one record)

#include <array>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/synthetic_stockinette.hpp"
#include "shell_fit/fit/synthetic_fabric.hpp"

namespace {

namespace fs = std::filesystem;
namespace db = yarnfit::db;
namespace shell = yarnfit::shell;
using db::format_g;

constexpr int k_digits = 6;
constexpr int k_stretch_points = 16;

struct StretchTest {
  db::Direction direction;
  double max_stretch;  // about 7 N at the end: beyond the 5 N power range the fit stops at
  bool gauge;          // read at gauge marks 80 mm along and 40 mm across
};

// One example record: its shell parameters [N/m, N·m] (the ground truth its curves are
// simulated from), its tile and its tests.
struct ExampleFabric {
  const char* id;
  const char* family;
  const char* header;       // the comment lines that open fabric.yaml
  const char* description;
  double areal_density_gsm;
  int denier, filaments;
  double stiffness_N;
  shell::ShellParams truth;
  db::StockinetteTileOptions tile;
  std::vector<StretchTest> tests;
  bool bending;
};

shell::ShellParams params(std::array<double, 6> inplane, std::array<double, 3> ktheta) {
  shell::ShellParams p;
  p.inplane = {inplane[0], inplane[1], inplane[2], inplane[3], inplane[4], inplane[5]};
  p.bending.ktheta = {ktheta[0], ktheta[1], ktheta[2]};
  return p;
}

db::StockinetteTileOptions tile(double radius, double period_x, double period_y) {
  db::StockinetteTileOptions t;
  t.yarn_radius = radius;
  t.period_x = period_x;
  t.period_y = period_y;
  return t;
}

// The bundled database (examples/fabrics): two families, three fabrics. stockinette_demo uses
// every key of the format; stockinette_light has no bias and no bending tests (so kss is held
// at its prior and k_θ is not fitted); interlock_demo is a stiffer double knit.
const std::vector<ExampleFabric>& examples() {
  static const std::vector<ExampleFabric> list{
      {"stockinette_demo", "single-jersey",
       "# Example fabric record made by yarnfit itself (examples/make_example.cpp).\n"
       "# Every key of the format is used; see docs/fabric-records.md for their meaning.\n",
       "Synthetic stockinette: project-generated tile; stretch and pear-loop curves simulated with the shell model "
       "from the parameters under ground_truth. Not a measurement.",
       180, 150, 48, 120, params({60.0, 12.0, 250.0, 20.0, 10.0, 5.0}, {2.0e-6, 2.6e-6, 3.4e-6}),
       db::StockinetteTileOptions{},
       {{db::Direction::weft, 0.8, false}, {db::Direction::bias, 0.65, false}, {db::Direction::warp, 0.3, true}},
       true},
      {"stockinette_light", "single-jersey",
       "# Example fabric record made by yarnfit itself (examples/make_example.cpp): a lighter\n"
       "# single jersey tested along weft and warp only, without pear-loop tests.\n",
       "Synthetic light stockinette: project-generated tile (finer yarn); weft and warp stretch curves simulated "
       "with the shell model from the parameters under ground_truth. Not a measurement.",
       130, 100, 36, 80, params({35.0, 8.0, 160.0, 12.0, 6.0, 3.0}, {1.2e-6, 1.5e-6, 2.0e-6}),
       tile(0.2e-3, 2.1e-3, 1.1e-3), {{db::Direction::weft, 0.9, false}, {db::Direction::warp, 0.35, false}}, false},
      {"interlock_demo", "double-knit",
       "# Example fabric record made by yarnfit itself (examples/make_example.cpp): a firmer knit\n"
       "# of a thicker yarn, tested along weft, bias and warp and in the pear loop.\n",
       "Synthetic firm knit: project-generated stockinette tile of a thicker yarn; stretch and pear-loop curves "
       "simulated with the shell model from the parameters under ground_truth. Not a measurement.",
       240, 200, 64, 160, params({110.0, 25.0, 320.0, 40.0, 18.0, 9.0}, {4.0e-6, 5.0e-6, 6.5e-6}),
       tile(0.3e-3, 2.7e-3, 1.45e-3),
       {{db::Direction::weft, 0.55, false}, {db::Direction::bias, 0.45, false}, {db::Direction::warp, 0.25, true}},
       true},
  };
  return list;
}

std::string fabric_yaml(const ExampleFabric& f) {
  const auto& k = f.truth.inplane;
  const auto& b = f.truth.bending.ktheta;
  std::ostringstream y;
  y << f.header << "id: " << f.id << "\nfamily: " << f.family << "\ndescription: \"" << f.description
    << "\"\nareal_density_gsm: " << format_g(f.areal_density_gsm) << "\nyarns:\n  - material: polyester\n    denier: "
    << f.denier << "\n    filaments: " << f.filaments << "\n    mass_fraction: 1.0\n    stiffness_N: "
    << format_g(f.stiffness_N) << "\npattern:\n  file: tile.pyp\n  weft_axis: x\nswatch: {length_mm: 100, width_mm: 60}\n"
    << "stretch_tests:\n";
  for (const auto& t : f.tests) {
    const std::string dir(db::to_string(t.direction));
    if (t.gauge) y << "  " << dir << ":\n    file: stretch_" << dir << ".csv\n    gauge: {length_mm: 80, width_mm: 40}\n";
    else y << "  " << dir << ": {file: stretch_" << dir << ".csv}\n";
  }
  if (f.bending) {
    y << "bending_tests:\n";
    for (const auto& t : f.tests) {
      const std::string dir(db::to_string(t.direction));
      y << "  " << dir << ": {file: bend_" << dir << ".csv}\n";
    }
  }
  y << "# The shell parameters the curves were simulated from (N/m; k_theta in N*m).\nground_truth: {"
    << "kxx: " << format_g(k.kxx) << ", kxy: " << format_g(k.kxy) << ", kyy: " << format_g(k.kyy)
    << ", kss: " << format_g(k.kss) << ", kn1: " << format_g(k.kn1) << ", kn2: " << format_g(k.kn2)
    << ", ktheta_weft: " << format_g(b[0]) << ", ktheta_bias: " << format_g(b[1]) << ", ktheta_warp: " << format_g(b[2])
    << "}\n";
  return y.str();
}

void write_example(const ExampleFabric& f, const fs::path& folder) {
  fs::create_directories(folder);
  shell::SyntheticShellOptions o;  // 10 × 6 cm swatch, 5 mm cells refined once, pear loop on 2 mm cells
  o.params = f.truth;
  o.areal_density = f.areal_density_gsm * 1e-3;
  db::write_text_file_atomically(folder / "fabric.yaml", fabric_yaml(f));
  db::write_pyp(db::make_stockinette_tile(f.tile), folder / "tile.pyp", 9);
  for (const auto& t : f.tests) {
    const std::string dir(db::to_string(t.direction));
    shell::ClampedStretchSetup setup = shell::synthetic_stretch_setup(o, t.direction);
    if (t.gauge) {
      setup.gauge_length = 0.080;
      setup.gauge_width = 0.040;
    }
    db::write_text_file_atomically(
        folder / ("stretch_" + dir + ".csv"),
        shell::simulate_stretch_csv(f.truth.inplane, setup, t.max_stretch, k_stretch_points,
                                    "synthetic " + dir + " stretch test simulated by examples/make_example.cpp",
                                    k_digits));
    if (!f.bending) continue;
    db::write_text_file_atomically(
        folder / ("bend_" + dir + ".csv"),
        shell::simulate_bending_csv(f.truth, shell::synthetic_bending_setup(o, t.direction),
                                    shell::synthetic_clamp_distances(o.bending_points),
                                    "synthetic " + dir + " pear-loop test simulated by examples/make_example.cpp",
                                    k_digits));
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage = "usage: yarnfit_make_example FOLDER [ID]   (one record, stockinette_demo by default)\n"
                            "       yarnfit_make_example --all DB      (every example, DB/<id>/)\n";
  if (argc < 2 || argc > 3) {
    std::cerr << usage;
    return 2;
  }
  try {
    if (std::string(argv[1]) == "--all") {
      if (argc != 3) {
        std::cerr << usage;
        return 2;
      }
      for (const auto& f : examples()) write_example(f, fs::path(argv[2]) / f.id);
      std::cout << "wrote " << examples().size() << " example fabrics to " << argv[2] << "\n";
      return 0;
    }
    const std::string id = argc == 3 ? argv[2] : "stockinette_demo";
    for (const auto& f : examples()) {
      if (id != f.id) continue;
      write_example(f, argv[1]);
      std::cout << "wrote example fabric " << id << " to " << argv[1] << "\n";
      return 0;
    }
    std::cerr << "yarnfit_make_example: no example " << id << "\n" << usage;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "yarnfit_make_example: " << e.what() << "\n";
    return 1;
  }
}
