#pragma once
// One uniform sample of a loaded yarn scene (SPEC §5 `yarnfit yarn sim`) and the records the
// yarn commands print: the sample's JSON {energy_density, stress_s, compression, converged,
// newton_iterations, seconds, effects, …} and the CSV of a free-compression stretch sweep
// (`yarn curve`). A solve that does not converge is a status, not an error: the record says
// converged false, the termination and the reason.

#include <Eigen/Core>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"
#include "yarn_fit/scenes/yarn_scene.hpp"

namespace yarnfit::yarn {

struct SceneSampleRequest {
  double stretch = 0.0;       // s = l/l̄ − 1 along the scene's direction
  double compression = 0.0;   // c = 1 − w/w̄ across it (ignored with free_compression)
  bool free_compression = false;  // find c with zero orthogonal stress
  double curvature = 0.0;     // κ along the direction [1/m]
  bool bending = false;       // also read σ_κ = dΨ/dκ (central differences)
};

struct SceneSample {
  CoarseDeformation chi;  // as requested (compression the given one)
  Sample sample;          // sample.chi holds the free compression when found
  std::optional<BendingSample> bend;
  Eigen::VectorXd g;      // the state the sample ended in
  int newton_iterations = 0;  // every solve of this sample (not the rest shape)
  int solves = 0;
  double seconds = 0.0;
  bool ok = false;            // the rest shape (when it ran), the sample and the bending read-out converged
  std::string termination;    // "converged"/"converged_readout", the failed solve's status, "compression_search", …
  std::string message;        // why not ok
  // The deformation the state `g` belongs to.
  [[nodiscard]] const CoarseDeformation& state_chi() const { return sample.ok ? sample.chi : chi; }
};

// How a sample ended: for a good one its last solve's converged status ("converged", or
// "converged_readout" when the stress read-out test ended it); else the failed solve's status,
// or "compression_search" when every solve converged but no zero-orthogonal-stress c was found.
[[nodiscard]] std::string termination(const Sample& sample);

// Simulates the request from the scene's start state (scene.g is left as it is).
SceneSample simulate_scene_sample(YarnScene& scene, const SceneSampleRequest& request);

// The `yarn sim` JSON of a sample: the request, the read-outs (null where the sample failed),
// convergence, iterations, effects, the rest shape, params, tile, units; `threads` and
// `total_seconds` (everything, the rest shape included) as the caller measured them.
nlohmann::json sample_json(const YarnScene& scene, const SceneSampleRequest& request, const SceneSample& sample,
                           int threads, double total_seconds);

// `yarn curve`'s CSV: direction,stretch,compression,energy_density_J_per_m2,stress_s_N_per_m,
// converged,newton_iterations,seconds,solves,stress_c_N_per_m,termination (read-outs empty
// where a point failed).
std::string sweep_csv(const std::string& direction, const StretchSweep& sweep);

}  // namespace yarnfit::yarn
