#pragma once
// Set-up shared by `yarnfit yarn sim` and `yarnfit yarn curve`: the options naming the pattern,
// the yarn parameters and the direction, the rest-shape heuristic (6.5.2) and solver limits;
// loading them into a periodic yarn system; the JSON records both commands print; and the
// OBJ dump of a tile state for inspection.

#include <CLI/CLI.hpp>

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"

namespace yarnfit::cli {

struct YarnSceneArgs {
  std::string pattern;      // pyp tile; its x axis is the weft (fabric.yaml's weft_axis: x)
  std::string params_file;  // YAML or JSON with the keys of yarn_fit.json's params
  std::string direction = "weft";
  double ks2 = 0.0;         // > 0: fills ks2, kc2, R2 the parameter file leaves out (SPEC §3)
  bool rest_shape = true;   // run the rest-shape heuristic before loading
  int rest_rounds = yarn::RestShapeOptions{}.rounds;
  int max_iterations = yarn::EquilibriumOptions{}.max_iterations;
  std::string compression_method = "root";  // root (∂Ψ/∂c = 0) or cobyla
  int threads = 1;
  bool quiet = false;
};

// --pattern, --params, --direction, --ks2, --rest-shape/--no-rest-shape, --rest-rounds,
// --max-iterations, --compression-method, --threads, -q/--quiet.
void add_yarn_scene_options(CLI::App& app, YarnSceneArgs& args);

// A loaded scene: the tile, parameters and system, and the state the simulation starts from.
struct YarnScene {
  db::PeriodicTile pattern;
  yarn::YarnParams params;
  std::unique_ptr<yarn::YarnSystem> system;
  Eigen::VectorXd g;  // start state: the relaxed rest state, or zeros (the affine state)
  double angle = 0.0;  // direction of the stretch from the weft (x) axis [rad]
  yarn::EquilibriumOptions solve;
  yarn::CompressionOptions compression;
  std::optional<yarn::RestShapeResult> rest;  // set when the heuristic ran
};

// Reads the pattern and the parameters. Every problem is appended as one line
// `file:line: field: message` (or `--option: value: message`); empty result then.
std::optional<YarnScene> load_yarn_scene(const YarnSceneArgs& args, std::vector<std::string>& problems);

// Runs the rest-shape heuristic when args.rest_shape; scene.g is then its relaxed state.
void prepare_rest_state(YarnScene& scene, const YarnSceneArgs& args);

// Direction name to the angle of the coarse deformation [rad]; weft 0, bias π/4, warp π/2.
double direction_angle(const std::string& direction);

nlohmann::json rest_shape_json(const YarnScene& scene);
nlohmann::json tile_json(const YarnScene& scene);
nlohmann::json units_json();

// Writes the tile state `g` under the coarse deformation `chi` as Wavefront OBJ: one `v`
// per vertex placement and one `l` polyline per periodic yarn (a yarn that advances by a
// period ends at the copy of its first vertex, a closed loop returns to it), deformed
// positions in metres relative to the tile centroid. `copies` = 1 writes the tile, 3 the
// 3 × 3 block of its periodic copies around it (one `o` object per copy). Returns the number
// of segments written per copy (the tile's edge count). Throws std::runtime_error naming the
// file when it cannot be written.
int write_tile_obj(const yarn::YarnSystem& system, const Eigen::VectorXd& g, const yarn::CoarseDeformation& chi,
                   const std::filesystem::path& file, int copies, const std::string& comment);

}  // namespace yarnfit::cli
