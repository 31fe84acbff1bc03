// Writes the bundled example fabric record, made entirely by the project:
//   FOLDER/fabric.yaml, tile.pyp, stretch_{weft,bias,warp}.csv, bend_{weft,bias,warp}.csv
//
// The tile is the project's own synthetic stockinette (fabrics_db/tile/synthetic_stockinette).
// The curves are simulated with the thin-shell model from the parameters written under
// ground_truth, by the library's synthetic-fabric writer (shell_fit/fit/synthetic_fabric):
//   * clamped stretch tests on the 10 × 6 cm swatch along weft, bias and warp (the warp test
//     read at gauge marks), 16 points each, on a mesh refined once from the fit's default
//     (5 mm cells subdivided to 2.5 mm), so a fit on its default mesh does not meet its own
//     discretisation;
//   * pear-loop tests at 7 clamp distances from 3 to 34 mm (the fit's targets) on 2 mm cells
//     (the bending fit uses 2.5 mm), from k_θ whose bending lengths (1.3–1.6 cm) are those of
//     a light knit; a simulated loop hangs as the shell model makes it, so the aspect ratios
//     stay above the weightless elastica's, which no k_θ could go below.
// The parameters are knit-like and of the magnitudes `yarnfit shell fit` finds on the acrylic
// records (tens to hundreds of N/m; the weft compliant, the warp stiff, a soft shear, lateral
// contraction shared between kxy and the area terms), chosen inside the fit's search range so
// that a fit on the example recovers them. Values are written with 6 significant digits: a
// regeneration on another build reproduces the committed files byte for byte.
//
// Usage: yarnfit_make_example FOLDER   (regenerates examples/fabrics/stockinette_demo)

#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

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

// The ground truth [N/m] and [N·m].
shell::ShellParams truth() {
  shell::ShellParams p;
  p.inplane = {60.0, 12.0, 250.0, 20.0, 10.0, 5.0};
  p.bending.ktheta = {2.0e-6, 2.6e-6, 3.4e-6};
  return p;
}

struct StretchTest {
  db::Direction direction;
  double max_stretch;  // about 7 N at the end: beyond the 5 N power range the fit stops at
  bool gauge;          // read at gauge marks 80 mm along and 40 mm across
};
constexpr StretchTest k_tests[] = {
    {db::Direction::weft, 0.8, false}, {db::Direction::bias, 0.65, false}, {db::Direction::warp, 0.3, true}};

std::string fabric_yaml(const shell::ShellParams& p) {
  const auto& k = p.inplane;
  const auto& b = p.bending.ktheta;
  std::ostringstream y;
  y << R"(# Example fabric record made by yarnfit itself (examples/make_example.cpp).
# Every key of the format is used; see docs/fabric-records.md for their meaning.
id: stockinette_demo
family: single-jersey
description: "Synthetic stockinette: project-generated tile; stretch and pear-loop curves simulated with the shell model from the parameters under ground_truth. Not a measurement."
areal_density_gsm: 180
yarns:
  - material: polyester
    denier: 150
    filaments: 48
    mass_fraction: 1.0
    stiffness_N: 120
pattern:
  file: tile.pyp
  weft_axis: x
swatch: {length_mm: 100, width_mm: 60}
stretch_tests:
  weft: {file: stretch_weft.csv}
  bias: {file: stretch_bias.csv}
  warp:
    file: stretch_warp.csv
    gauge: {length_mm: 80, width_mm: 40}
bending_tests:
  weft: {file: bend_weft.csv}
  bias: {file: bend_bias.csv}
  warp: {file: bend_warp.csv}
# The shell parameters the curves were simulated from (N/m; k_theta in N*m).
ground_truth: {)"
    << "kxx: " << format_g(k.kxx) << ", kxy: " << format_g(k.kxy) << ", kyy: " << format_g(k.kyy)
    << ", kss: " << format_g(k.kss) << ", kn1: " << format_g(k.kn1) << ", kn2: " << format_g(k.kn2)
    << ", ktheta_weft: " << format_g(b[0]) << ", ktheta_bias: " << format_g(b[1]) << ", ktheta_warp: " << format_g(b[2])
    << "}\n";
  return y.str();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: yarnfit_make_example FOLDER\n";
    return 2;
  }
  const fs::path folder = argv[1];
  try {
    fs::create_directories(folder);
    const shell::ShellParams params = truth();
    shell::SyntheticShellOptions o;  // 10 × 6 cm swatch, 5 mm cells refined once, pear loop on 2 mm cells
    o.params = params;
    o.areal_density = 0.180;
    db::write_text_file_atomically(folder / "fabric.yaml", fabric_yaml(params));
    db::write_pyp(db::make_stockinette_tile(db::StockinetteTileOptions{}), folder / "tile.pyp", 9);
    for (const auto& t : k_tests) {
      const std::string dir(db::to_string(t.direction));
      shell::ClampedStretchSetup setup = shell::synthetic_stretch_setup(o, t.direction);
      if (t.gauge) {
        setup.gauge_length = 0.080;
        setup.gauge_width = 0.040;
      }
      db::write_text_file_atomically(
          folder / ("stretch_" + dir + ".csv"),
          shell::simulate_stretch_csv(params.inplane, setup, t.max_stretch, k_stretch_points,
                                      "synthetic " + dir + " stretch test simulated by examples/make_example.cpp",
                                      k_digits));
      db::write_text_file_atomically(
          folder / ("bend_" + dir + ".csv"),
          shell::simulate_bending_csv(params, shell::synthetic_bending_setup(o, t.direction),
                                      shell::synthetic_clamp_distances(o.bending_points),
                                      "synthetic " + dir + " pear-loop test simulated by examples/make_example.cpp",
                                      k_digits));
    }
  } catch (const std::exception& e) {
    std::cerr << "yarnfit_make_example: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote example fabric to " << folder.string() << "\n";
  return 0;
}
