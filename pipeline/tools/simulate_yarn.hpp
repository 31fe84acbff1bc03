#pragma once
// `yarn sim` and `yarn curve` as one library call each: a periodic yarn tile read from files,
// optionally relaxed to its rest shape (6.5.2), then simulated under one uniform coarse
// deformation (a sample) or swept in stretch with free compression (a curve), with the OBJ
// dumps of its states (yarn_fit/scenes/).
//
// A solve that does not converge is an outcome, not an error: the sample's JSON or the curve's
// CSV is still written, with converged false and the reason.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "numerics/progress.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::pipeline {

// The tile, its parameters and how both commands solve it.
struct YarnSceneRequest {
  yarn::YarnSceneSetup setup;  // the tile, the parameter file, the direction and the solves' settings
  std::string compression_method = "root";  // root (∂Ψ/∂c = 0) or cobyla: setup.compression
  int threads = 1;
};

struct YarnSimRequest {
  YarnSceneRequest scene;
  double stretch = 0.0;      // s = l/l̄ − 1 along the direction
  double compression = 0.0;  // c = 1 − w/w̄ across it
  bool free_compression = false;
  std::optional<double> curvature;  // κ along the direction [1/m]; set: σ_κ is read too
  std::string dump;                 // OBJ of the final state; empty: none
  bool dump_neighbours = false;     // the 3 × 3 block of periodic copies
};

struct YarnSimOutcome {
  nlohmann::json json;  // sample_json: the request, the read-outs, convergence, the rest shape
  std::string summary;  // the same for a reader
  bool converged = false;
  std::string failure;       // why not converged
  std::string dump_failure;  // `file: file: what` when the OBJ could not be written
};

struct YarnCurveRequest {
  YarnSceneRequest scene;
  double max_stretch = 0.0;
  int points = 20;       // evenly from 0 to max_stretch
  std::string out;       // the CSV, replaced if it exists
  std::string dump_dir;  // one OBJ per point; empty: none
  bool dump_neighbours = false;
};

struct YarnCurveOutcome {
  std::string summary;                // the sweep as a table, and what was written
  std::vector<std::string> failures;  // one line per point, rest shape or dump that failed
  bool ok = false;                    // every point and the rest shape converged, every file written
};

// Each checks the request first (problems name its fields, the files read, or the outputs that
// cannot be placed) and simulates nothing when there is a problem. `progress` sees the stages
// (the rest shape, the solve) and, for a curve, each point. The curve's CSV is written
// atomically; one that cannot be written throws an Error naming it.
[[nodiscard]] YarnSimOutcome simulate_yarn_sample(const YarnSimRequest& request, db::Problems& problems,
                                                  const numerics::ProgressFn& progress = {});
[[nodiscard]] YarnCurveOutcome sweep_yarn_stretch(const YarnCurveRequest& request, db::Problems& problems,
                                                  const numerics::ProgressFn& progress = {});

}  // namespace yarnfit::pipeline
