#pragma once
// Synthetic fabric records whose curves are simulated from known shell parameters (SPEC §6:
// the project's own examples and tests): clamped stretch tests from the in-plane parameters
// and, when asked, pear-loop bending tests from k_θ. The parameters are written under
// ground_truth, so a fit can be checked against them.
//
// The curve functions are public so that other writers (examples/make_example.cpp, which adds
// a tile and a yarn composition) and `yarnfit shell sim` run exactly the scenes of
// `yarnfit synth shell`.

#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/scenes/clamped_stretch.hpp"
#include "shell_fit/scenes/pear_loop.hpp"

namespace yarnfit::shell {

struct SyntheticShellOptions {
  std::string id = "synthetic_shell";
  std::string family = "synthetic";
  ShellParams params;
  // Stretch tests: largest stretch per direction; curves from 0 in `points` even steps.
  std::map<db::Direction, double> max_stretch{{db::Direction::weft, 0.8}, {db::Direction::bias, 0.6},
                                              {db::Direction::warp, 0.4}};
  double length = 0.10;                 // swatch [m]
  double width = 0.06;
  std::optional<double> gauge_length;   // [m]
  std::optional<double> gauge_width;    // [m]
  int points = 13;                      // per curve, evenly spaced from 0
  double target_edge = 5e-3;            // mesh of the stretch simulations [m]
  int refinements = 1;                  // a different mesh than the fit's default
  double noise = 0.0;                   // relative Gaussian noise on force and compression (and r)
  unsigned seed = 1;
  // Pear-loop tests, simulated from params.bending on the swatch's strip; none by default.
  std::vector<db::Direction> bending_directions;
  int bending_points = 7;               // clamp distances evenly over [3, 34] mm (the fit's targets)
  double areal_density = 0.18;          // [kg/m²]; written as areal_density_gsm
  // The pear loop's mesh: 2 mm cells, unlike the bending fit's 2.5 mm (a different mesh at a
  // similar cost; a refinement would make every loop several times slower:
  // docs/shell-fit.md).
  double bending_target_edge = 2e-3;
  int bending_refinements = 0;
};

// The scenes the writer simulates for one test direction.
ClampedStretchSetup synthetic_stretch_setup(const SyntheticShellOptions& options, db::Direction direction);
PearLoopSetup synthetic_bending_setup(const SyntheticShellOptions& options, db::Direction direction);

// The CSV text of a simulated stretch test: a comment line, the header
// "stretch,force_N,compression", the rest state 0,0,0 and one row per stretch
// s_max·i/(points − 1), i = 1 … points − 1, values with `digits` significant digits. With
// `noise` > 0 each force and compression is multiplied by 1 + noise·N(0, 1) drawn from `rng`
// (force clipped at 0). Throws an Error when a simulation fails.
std::string simulate_stretch_csv(const InplaneParams& params, const ClampedStretchSetup& setup, double max_stretch,
                                 int points, const std::string& comment, int digits = 12, double noise = 0.0,
                                 std::mt19937* rng = nullptr);

// The clamp distances of a synthetic bending test: `points` evenly over [3, 34] mm [m].
std::vector<double> synthetic_clamp_distances(int points);

// The CSV text of a simulated pear-loop test: a comment line, the header
// "clamp_distance_mm,aspect_ratio,height_mm,width_mm" (the last two informative) and one row
// per distance [m]. Noise as above, on the aspect ratio. Throws an Error when a
// loop does not reach equilibrium.
std::string simulate_bending_csv(const ShellParams& params, const PearLoopSetup& setup,
                                 const std::vector<double>& clamp_distances, const std::string& comment,
                                 int digits = 12, double noise = 0.0, std::mt19937* rng = nullptr);

// Simulates the tests and writes FOLDER/fabric.yaml, stretch_<dir>.csv and, with bending
// directions, bend_<dir>.csv. Throws an input Error for options that cannot be
// simulated (e.g. a bending test without positive k_θ or density), an Error when a
// simulation fails or a file cannot be written; refuses to replace an existing fabric.yaml
// unless `overwrite`.
void write_synthetic_shell_fabric(const SyntheticShellOptions& options, const std::filesystem::path& folder,
                                  bool overwrite = false);

}  // namespace yarnfit::shell
