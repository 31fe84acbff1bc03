#pragma once
// One periodic yarn tile set up for simulation from files (SPEC §5 `yarnfit yarn sim`,
// `yarn curve`): the pattern and the yarn parameters read and checked, the periodic system
// built, optionally relaxed to its rest shape (6.5.2), and the JSON records and OBJ dumps the
// yarn commands write about it.

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

struct YarnSceneSetup {
  std::filesystem::path pattern;  // pyp tile; its x axis is the weft (fabric.yaml's weft_axis: x)
  std::filesystem::path params;   // YAML or JSON with the keys of yarn_fit.json's params
  std::string direction = "weft";  // weft, bias or warp
  double ks2 = 0.0;  // > 0: fills ks2, kc2, R2 the parameter file leaves out (SPEC §3)
  bool rest_shape = true;  // run the rest-shape heuristic before simulating
  int rest_rounds = RestShapeOptions{}.rounds;
  int max_iterations = EquilibriumOptions{}.max_iterations;  // per equilibrium solve
  // The stress read-out test of the solves [N/m] (EquilibriumOptions::stress_tolerance):
  // < 0 = default_stress_tolerance of the tile and parameters, 0 = off.
  double stress_tolerance = EquilibriumOptions{}.stress_tolerance;
  CompressionMethod compression = CompressionMethod::root_find;
};

// A loaded scene: the tile, parameters and system, and the state the simulation starts from.
struct YarnScene {
  std::string pattern_file;  // as given
  std::string direction;     // weft, bias or warp
  db::PeriodicTile pattern;
  YarnParams params;
  std::unique_ptr<YarnSystem> system;
  Eigen::VectorXd g;  // start state: the relaxed rest state, or zeros (the affine state)
  double angle = 0.0;  // direction of the stretch from the weft (x) axis [rad]
  EquilibriumOptions solve;
  CompressionOptions compression;
  std::optional<RestShapeResult> rest;  // set when the heuristic ran
};

// Direction name to the angle of the coarse deformation [rad]; weft 0, bias π/4, warp π/2.
[[nodiscard]] double direction_angle(const std::string& direction);
// The parameter scales of a tile for a yarn stiffness ks2 [N] > 0 (R_est from the tile facts).
[[nodiscard]] ParameterScales scales_of(const db::PeriodicTile& tile, double ks2);
// "root" or "cobyla".
[[nodiscard]] const char* to_string(CompressionMethod method);

// Reads the pattern and the parameters. Every problem is added as `file:line: field: message`
// (a missing ks2, kc2 or R2 as field `ks2`… with message "missing"); empty result then.
std::optional<YarnScene> load_yarn_scene(const YarnSceneSetup& setup, db::Problems& problems);

// Runs the rest-shape heuristic when setup.rest_shape; scene.g is then its relaxed state.
void prepare_rest_state(YarnScene& scene, const YarnSceneSetup& setup);

nlohmann::json rest_shape_json(const YarnScene& scene);
nlohmann::json tile_json(const YarnScene& scene);
nlohmann::json units_json();

// Writes the tile state `g` under the coarse deformation `chi` as Wavefront OBJ: one `v`
// per vertex placement and one `l` polyline per periodic yarn (a yarn that advances by a
// period ends at the copy of its first vertex, a closed loop returns to it), deformed
// positions in metres relative to the tile centroid. `copies` = 1 writes the tile, 3 the
// 3 × 3 block of its periodic copies around it (one `o` object per copy). Returns the number
// of segments written per copy (the tile's edge count). Throws an Error naming the
// file when it cannot be written.
int write_tile_obj(const YarnSystem& system, const Eigen::VectorXd& g, const CoarseDeformation& chi,
                   const std::filesystem::path& file, int copies, const std::string& comment);

}  // namespace yarnfit::yarn
