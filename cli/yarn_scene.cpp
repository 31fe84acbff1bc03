#include "cli/yarn_scene.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::cli {

using nlohmann::json;

void add_yarn_scene_options(CLI::App& app, YarnSceneArgs& a) {
  app.add_option("--pattern", a.pattern, "Periodic yarn tile (HYLC pyp, metres); its x axis is the weft")->required();
  app.add_option("--params", a.params_file,
                 "Yarn parameters, YAML or JSON, SI units, keys of yarn_fit.json's params: ks1, eps_s, kb, R1, "
                 "kc1, ks2, kc2, R2 (a yarn_fit.json itself is accepted)")
      ->required();
  app.add_option("--direction", a.direction, "Stretch direction: weft (0 deg), bias (45 deg) or warp (90 deg)")
      ->check(CLI::IsMember({"weft", "bias", "warp"}))
      ->capture_default_str();
  app.add_option("--ks2", a.ks2,
                 "Stiffest yarn's stiffness [N]: fills ks2, kc2 = 1e3 ks2/R_est and R2 = 0.25 R_est when the "
                 "parameter file leaves them out (SPEC 3)");
  app.add_flag("--rest-shape,!--no-rest-shape", a.rest_shape,
               "Estimate yarn rest shapes first (thesis 6.5.2: the tile is then nearly stress-free at rest, as in "
               "the yarn fit); --no-rest-shape simulates the rest lengths and curvatures of the file (default: "
               "rest shape on)");
  app.add_option("--rest-rounds", a.rest_rounds, "Rounds of the rest-shape heuristic")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--max-iterations", a.max_iterations, "Newton iterations per equilibrium solve")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  app.add_option("--compression-method", a.compression_method,
                 "Zero-orthogonal-stress compression: root (root find on dPsi/dc, default) or cobyla (as in "
                 "the thesis)")
      ->check(CLI::IsMember({"root", "cobyla"}))
      ->capture_default_str();
  app.add_option("--threads", a.threads, "OpenMP threads for the simulation's parallel loops (the yarn solver is serial today)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_flag("-q,--quiet", a.quiet, "No progress and no summary (JSON output is still printed)");
}

double direction_angle(const std::string& direction) {
  if (direction == "bias") return yarn::bias_angle();
  if (direction == "warp") return yarn::warp_angle();
  return yarn::weft_angle();
}

std::optional<YarnScene> load_yarn_scene(const YarnSceneArgs& a, std::vector<std::string>& problems) {
  const std::size_t before = problems.size();
  if (!(std::isfinite(a.ks2) && a.ks2 >= 0.0))
    problems.push_back("--ks2: " + db::format_g(a.ks2) + ": must be a positive stiffness [N]");
  db::Problems found;
  YarnScene scene;
  std::optional<yarn::YarnTile> tile;
  std::optional<yarn::ParameterScales> scales;
  if (auto pyp = db::read_pyp(a.pattern, found)) {
    scene.pattern = std::move(*pyp);
    try {
      tile = yarn::make_yarn_tile(scene.pattern);
      if (a.ks2 > 0.0) scales = yarn::ParameterScales{a.ks2, db::compute_tile_facts(scene.pattern).r_est};
    } catch (const std::invalid_argument& e) {
      found.add(a.pattern, 0, "file", std::string("not a usable periodic tile: ") + e.what());
    }
  }
  const auto params = yarn::read_yarn_params(a.params_file, scales, found);
  bool fixed_missing = false;
  for (const auto& p : found.items()) {
    problems.push_back(p.to_string());
    fixed_missing = fixed_missing || ((p.field == "ks2" || p.field == "kc2" || p.field == "R2") && p.message == "missing");
  }
  if (fixed_missing && !(a.ks2 > 0.0))
    problems.push_back("--ks2: not given: write ks2, kc2 and R2 in " + a.params_file +
                       ", or pass --ks2 N to derive the missing ones from the tile");
  if (problems.size() != before || !tile || !params) return std::nullopt;

  scene.params = *params;
  scene.system = std::make_unique<yarn::YarnSystem>(std::move(*tile), scene.params);
  scene.g = Eigen::VectorXd::Zero(scene.system->dof_count());
  scene.angle = direction_angle(a.direction);
  scene.solve.max_iterations = a.max_iterations;
  scene.compression.method =
      a.compression_method == "cobyla" ? yarn::CompressionMethod::cobyla : yarn::CompressionMethod::root_find;
  return scene;
}

void prepare_rest_state(YarnScene& scene, const YarnSceneArgs& a) {
  if (!a.rest_shape) return;
  yarn::RestShapeOptions options;
  options.rounds = a.rest_rounds;
  options.solve = scene.solve;
  scene.rest = yarn::relax_rest_shape(*scene.system, scene.g, options);
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
          {"termination", yarn::to_string(r.last_solve.status)},
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

int write_tile_obj(const yarn::YarnSystem& system, const Eigen::VectorXd& g, const yarn::CoarseDeformation& chi,
                   const std::filesystem::path& file, int copies, const std::string& comment) {
  const yarn::YarnTile& tile = system.tile();
  const yarn::CoarseMap map(chi);
  const auto position = [&](int v, const yarn::Cell& cell) {
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
          const Eigen::Vector3d x = position(edge.v0, edge.cycle_cell + yarn::Cell{ci, cj});
          out << "v " << x.x() << " " << x.y() << " " << x.z() << "\n";
          ++next;
        }
        const bool closed = yarn.net_offset == yarn::Cell{0, 0};
        if (!closed) {
          const auto& last = tile.edges[static_cast<std::size_t>(yarn.edges.back())];
          const Eigen::Vector3d x = position(last.v1, last.cycle_cell + last.cell1 + yarn::Cell{ci, cj});
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

}  // namespace yarnfit::cli
