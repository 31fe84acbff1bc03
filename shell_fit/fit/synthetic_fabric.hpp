#pragma once
// Synthetic fabric records whose stretch curves are simulated from known shell parameters
// (SPEC §6: the project's own examples and tests). The parameters are written under
// ground_truth, so a fit can be checked against them.

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

struct SyntheticShellOptions {
  std::string id = "synthetic_shell";
  std::string family = "synthetic";
  ShellParams params;
  std::map<db::Direction, double> max_stretch{{db::Direction::weft, 0.8}, {db::Direction::bias, 0.6},
                                              {db::Direction::warp, 0.4}};
  double length = 0.10;                 // swatch [m]
  double width = 0.06;
  std::optional<double> gauge_length;   // [m]
  std::optional<double> gauge_width;    // [m]
  int points = 13;                      // per curve, evenly spaced from 0
  double target_edge = 5e-3;            // mesh of the simulation [m]
  int refinements = 1;                  // a different mesh than the fit's default
  double noise = 0.0;                   // relative Gaussian noise on force and compression
  unsigned seed = 1;
};

// Simulates the tests and writes FOLDER/fabric.yaml and stretch_<dir>.csv. Throws
// std::runtime_error when a simulation fails or a file cannot be written; refuses to
// replace an existing fabric.yaml unless `overwrite`.
void write_synthetic_shell_fabric(const SyntheticShellOptions& options, const std::filesystem::path& folder,
                                  bool overwrite = false);

}  // namespace yarnfit::shell
