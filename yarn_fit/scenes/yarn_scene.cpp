#include "yarn_fit/scenes/yarn_scene.hpp"

#include <sstream>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/periodic/coarse_map.hpp"

namespace yarnfit::yarn {

using nlohmann::json;

double direction_angle(const std::string& direction) {
  if (direction == "bias") return bias_angle();
  if (direction == "warp") return warp_angle();
  return weft_angle();
}

ParameterScales scales_of(const db::PeriodicTile& tile, double ks2) {
  return ParameterScales{ks2, db::compute_tile_facts(tile).r_est};
}

const char* to_string(CompressionMethod method) {
  return method == CompressionMethod::cobyla ? "cobyla" : "root";
}

std::optional<YarnScene> load_yarn_scene(const YarnSceneSetup& setup, db::Problems& problems) {
  const std::size_t before = problems.size();
  YarnScene scene;
  scene.pattern_file = setup.pattern.string();
  scene.direction = setup.direction;
  std::optional<YarnTile> tile;
  std::optional<ParameterScales> scales;
  if (auto pyp = db::read_pyp(setup.pattern, problems)) {
    scene.pattern = std::move(*pyp);
    try {
      tile = make_yarn_tile(scene.pattern);
      if (setup.ks2 > 0.0) scales = scales_of(scene.pattern, setup.ks2);
    } catch (const Error& e) {
      problems.add(setup.pattern.string(), 0, "file", std::string("not a usable periodic tile: ") + e.what());
    }
  }
  const auto params = read_yarn_params(setup.params, scales, problems);
  if (problems.size() != before || !tile || !params) return std::nullopt;

  scene.params = *params;
  scene.system = std::make_unique<YarnSystem>(std::move(*tile), scene.params);
  scene.g = Eigen::VectorXd::Zero(scene.system->dof_count());
  scene.angle = direction_angle(setup.direction);
  scene.solve.max_iterations = setup.max_iterations;
  scene.solve.stress_tolerance = setup.stress_tolerance;
  scene.compression.method = setup.compression;
  return scene;
}

void prepare_rest_state(YarnScene& scene, const YarnSceneSetup& setup) {
  if (!setup.rest_shape) return;
  RestShapeOptions options;
  options.rounds = setup.rest_rounds;
  options.solve = scene.solve;
  scene.rest = relax_rest_shape(*scene.system, scene.g, options);
}

namespace {
json matrix_json(const Eigen::Matrix2d& m) {
  return json::array({json::array({m(0, 0), m(0, 1)}), json::array({m(1, 0), m(1, 1)})});
}
}  // namespace

json rest_shape_json(const YarnScene& scene) {
  if (!scene.rest) return {{"applied", false}};
  const auto& r = *scene.rest;
  return {{"applied", true},
          {"converged", r.converged},
          {"termination", to_string(r.last_solve.status)},
          {"message", r.last_solve.message},
          {"rounds", r.rounds},
          {"newton_iterations", r.newton_iterations},
          {"rest_stress_N_per_m", matrix_json(r.rest_stress)},
          {"max_length_change", r.max_length_change},
          {"clamped_edges", r.clamped_edges},
          {"seconds", r.seconds}};
}

json tile_json(const YarnScene& scene) {
  const auto& t = scene.system->tile();
  return {{"vertices", t.vertex_count()},
          {"edges", t.edge_count()},
          {"yarns", t.yarns.size()},
          {"period_m", json::array({scene.pattern.period_x, scene.pattern.period_y})},
          {"area_m2", t.area()},
          {"radius_m", t.radius}};
}

json units_json() {
  return {{"energy_density", "J/m^2"}, {"stress_s", "N/m"},       {"stress_c", "N/m"},
          {"coarse_stress", "N/m"},    {"stress_kappa", "N"},     {"curvature", "1/m"},
          {"stretch", "l/l0 - 1"},     {"compression", "1 - w/w0"}, {"seconds", "s"}};
}

int write_tile_obj(const YarnSystem& system, const Eigen::VectorXd& g, const CoarseDeformation& chi,
                   const std::filesystem::path& file, int copies, const std::string& comment) {
  const YarnTile& tile = system.tile();
  const CoarseMap map(chi);
  const auto position = [&](int v, const Cell& cell) {
    Eigen::Vector3d base;
    Eigen::Matrix3d rotation;
    map.place(tile.reference_at(v, cell), base, rotation);
    return Eigen::Vector3d(base + rotation * g.segment<3>(3 * v));
  };
  const int reach = copies / 2;
  std::ostringstream out;
  out.precision(9);
  out << "# yarnfit: " << comment << "\n"
      << "# stretch " << chi.stretch << ", compression " << chi.compression << ", curvature " << chi.curvature
      << " 1/m, direction " << chi.angle << " rad from the weft (x); metres, relative to the tile centroid\n"
      << "# one polyline (l) per periodic yarn; " << copies << " x " << copies << " periodic copies; "
      << tile.edge_count() << " segments per copy\n";
  int next = 1;  // OBJ indices are 1-based
  int segments = 0;
  for (int ci = -reach; ci <= reach; ++ci) {
    for (int cj = -reach; cj <= reach; ++cj) {
      out << "o tile_" << ci << "_" << cj << "\n";
      segments = 0;
      for (std::size_t y = 0; y < tile.yarns.size(); ++y) {
        const auto& yarn = tile.yarns[y];
        if (yarn.edges.empty()) continue;
        out << "g yarn_" << y << "\n";
        const int first = next;
        for (const int e : yarn.edges) {
          const auto& edge = tile.edges[static_cast<std::size_t>(e)];
          const Eigen::Vector3d x = position(edge.v0, edge.cycle_cell + Cell{ci, cj});
          out << "v " << x.x() << " " << x.y() << " " << x.z() << "\n";
          ++next;
        }
        const bool closed = yarn.net_offset == Cell{0, 0};
        if (!closed) {
          const auto& last = tile.edges[static_cast<std::size_t>(yarn.edges.back())];
          const Eigen::Vector3d x = position(last.v1, last.cycle_cell + last.cell1 + Cell{ci, cj});
          out << "v " << x.x() << " " << x.y() << " " << x.z() << "\n";
          ++next;
        }
        out << "l";
        for (int i = first; i < next; ++i) out << " " << i;
        if (closed) out << " " << first;
        out << "\n";
        segments += static_cast<int>(yarn.edges.size());
      }
    }
  }
  db::write_text_file_atomically(file, out.str());
  return segments;
}

}  // namespace yarnfit::yarn
