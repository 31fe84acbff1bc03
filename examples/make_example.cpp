// Writes the bundled example fabric record, made entirely by the project:
//   FOLDER/fabric.yaml, tile.pyp, stretch_{weft,bias,warp}.csv, bend_{weft,bias,warp}.csv
//
// The tile is the project's own synthetic stockinette (fabrics_db/tile/synthetic_stockinette).
// The curves are analytic and merely plausible for a knit — line force f(s) = a·s + b·s³,
// compression c(s) = 1 − (1+s)^−ν, pear-loop aspect ratio falling linearly with the clamp
// distance — so the record exercises every part of the format. They are not measurements and
// not a simulation; ground_truth is left empty for that reason.
//
// Usage: yarnfit_make_example FOLDER   (regenerates examples/fabrics/stockinette_demo)

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/synthetic_stockinette.hpp"

namespace {

namespace fs = std::filesystem;
using yarnfit::db::format_g;

constexpr double k_swatch_width = 0.06;  // m, the thesis's 10 × 6 cm swatch
constexpr int k_stretch_points = 16;
constexpr int k_bend_points = 7;

struct StretchLaw {
  const char* direction;
  double a, b;     // line force f = a s + b s³ [N/m]
  double nu;       // lateral contraction exponent
  double s_max;    // largest stretch of the test
};

std::string stretch_csv(const StretchLaw& law) {
  std::ostringstream out;
  out << "# synthetic " << law.direction << " stretch test made by examples/make_example.cpp\n";
  out << "stretch,force_N,compression\n";
  for (int i = 0; i < k_stretch_points; ++i) {
    const double s = law.s_max * i / (k_stretch_points - 1);
    const double force = (law.a * s + law.b * s * s * s) * k_swatch_width;
    const double c = 1.0 - std::pow(1.0 + s, -law.nu);
    out << format_g(s, 6) << "," << format_g(force, 6) << "," << format_g(c, 6) << "\n";
  }
  return out.str();
}

std::string bend_csv(const char* direction, double r0, double slope_per_mm) {
  std::ostringstream out;
  out << "# synthetic " << direction << " pear-loop test made by examples/make_example.cpp\n";
  out << "clamp_distance_mm,aspect_ratio\n";
  for (int i = 0; i < k_bend_points; ++i) {
    const double d = 3.0 + (34.0 - 3.0) * i / (k_bend_points - 1);
    out << format_g(d, 6) << "," << format_g(r0 - slope_per_mm * d, 6) << "\n";
  }
  return out.str();
}

const char* k_fabric_yaml = R"(# Example fabric record made by yarnfit itself (examples/make_example.cpp).
# Every key of the format is used; see docs/fabric-records.md for their meaning.
id: stockinette_demo
family: single-jersey
description: "Synthetic stockinette: project-generated tile and analytic curves plausible for a knit. Not a measurement."
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
ground_truth: {}
)";

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: yarnfit_make_example FOLDER\n";
    return 2;
  }
  const fs::path folder = argv[1];
  try {
    fs::create_directories(folder);
    yarnfit::db::write_text_file_atomically(folder / "fabric.yaml", k_fabric_yaml);
    yarnfit::db::write_pyp(yarnfit::db::make_stockinette_tile(yarnfit::db::StockinetteTileOptions{}),
                           folder / "tile.pyp", 9);
    // Weft (courses) is the compliant direction of a single jersey, warp (wales) the stiff one.
    const StretchLaw laws[] = {{"weft", 8.0, 120.0, 0.45, 0.9},
                               {"bias", 12.0, 250.0, 0.60, 0.7},
                               {"warp", 20.0, 600.0, 0.35, 0.5}};
    for (const auto& law : laws) {
      yarnfit::db::write_text_file_atomically(folder / ("stretch_" + std::string(law.direction) + ".csv"),
                                              stretch_csv(law));
    }
    yarnfit::db::write_text_file_atomically(folder / "bend_weft.csv", bend_csv("weft", 1.38, 0.0090));
    yarnfit::db::write_text_file_atomically(folder / "bend_bias.csv", bend_csv("bias", 1.36, 0.0085));
    yarnfit::db::write_text_file_atomically(folder / "bend_warp.csv", bend_csv("warp", 1.33, 0.0080));
  } catch (const std::exception& e) {
    std::cerr << "yarnfit_make_example: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote example fabric to " << folder.string() << "\n";
  return 0;
}
