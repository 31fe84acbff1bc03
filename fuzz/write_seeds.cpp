// Writes the seed corpus of every fuzz target: FOLDER/<target>/<seed>, from what the project
// makes itself: the example records yarnfit simulated (examples/fabrics/stockinette_*), tiles
// from its own generators, result files it wrote (tests/results/data), checkpoints and
// targets written by its own writers, and the public FAB examples of tests/data/fab, thinned.
// Never anything from ../shared.
//   write_seeds SOURCE_DIR FOLDER
#include <archive.h>
#include <archive_entry.h>

#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "yarn_fit/fit/fit_checkpoint.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/knit_tile.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "results/shell_fit_file.hpp"
#include "results/tile_file.hpp"
#include "results/yarn_fit_file.hpp"
#include "swarm/swarm_state.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace fs = std::filesystem;
using namespace yarnfit;

namespace {

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error(file.string() + ": cannot write");
}

// A record folder as one input in fuzz_support.hpp's split layout.
std::string record_as_input(const fs::path& folder) {
  std::string text = read_text(folder / "fabric.yaml");
  std::vector<fs::path> others;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.path().filename() != "fabric.yaml") others.push_back(e.path());
  std::sort(others.begin(), others.end());
  for (const auto& f : others) text += "==> " + f.filename().string() + " <==\n" + read_text(f);
  return text;
}

// The record's files as an archive in `format` (ARCHIVE_FORMAT_*), under a top folder.
std::string record_as_archive(const fs::path& folder, int format, bool gzip) {
  std::vector<char> buffer(1 << 22);
  std::size_t used = 0;
  archive* a = archive_write_new();
  archive_write_set_format(a, format);
  if (gzip) archive_write_add_filter_gzip(a);
  archive_write_set_bytes_in_last_block(a, 1);
  if (archive_write_open_memory(a, buffer.data(), buffer.size(), &used) != ARCHIVE_OK)
    throw std::runtime_error(archive_error_string(a));
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const std::string body = read_text(f);
    archive_entry* e = archive_entry_new();
    archive_entry_set_pathname(e, (folder.filename() / f.filename()).string().c_str());
    archive_entry_set_size(e, static_cast<la_int64_t>(body.size()));
    archive_entry_set_filetype(e, AE_IFREG);
    archive_entry_set_perm(e, 0644);
    archive_write_header(a, e);
    archive_write_data(a, body.data(), body.size());
    archive_entry_free(e);
  }
  archive_write_close(a);
  archive_write_free(a);
  return std::string(buffer.data(), used);
}

// Every array longer than 40 kept at every `step`-th element (the FAB's parallel sample arrays
// stay parallel): the public examples at a size the fuzzer mutates quickly.
void thin(nlohmann::json& j, std::size_t step) {
  if (j.is_array() && j.size() > 40) {
    nlohmann::json kept = nlohmann::json::array();
    for (std::size_t i = 0; i < j.size(); i += step) kept.push_back(j[i]);
    j = kept;
  }
  if (j.is_array() || j.is_object())
    for (auto& child : j) thin(child, step);
}

db::WovenTileOptions woven_options() {
  db::WovenTileOptions o;
  o.yarn_spacing = 1.5e-3;
  o.yarn_radius = 0.25e-3;
  return o;
}

db::KnitTileOptions knit_options() {
  db::KnitTileOptions o;
  o.yarn_radius = 0.25e-3;
  o.stitch_length = 5e-3;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: write_seeds SOURCE_DIR FOLDER\n";
    return 2;
  }
  const fs::path source = argv[1];
  const fs::path out = argv[2];
  const fs::path examples = source / "examples/fabrics";
  const std::vector<std::string> records = {"stockinette_demo", "stockinette_light"};

  for (const auto& r : records) {
    write_text(out / "fabric_record" / r, record_as_input(examples / r));
    write_text(out / "archive_upload" / (r + ".tar.gz"),
               record_as_archive(examples / r, ARCHIVE_FORMAT_TAR_PAX_RESTRICTED, true));
    write_text(out / "archive_upload" / (r + ".zip"), record_as_archive(examples / r, ARCHIVE_FORMAT_ZIP, false));
    write_text(out / "pyp_tile" / (r + ".pyp"), read_text(examples / r / "tile.pyp"));
  }

  // Tiles from the generators, at few digits (short inputs).
  for (const std::string weave : {"plain", "twill2x2"}) {
    const auto tile = db::make_woven_tile(*db::parse_weave_chart(weave), woven_options());
    db::write_pyp(tile, out / "pyp_tile" / (weave + ".pyp"), 6);
  }
  const auto knit = db::make_knit_tile(*db::parse_knit_chart("kp/pk"), knit_options());
  db::write_pyp(knit.tile, out / "pyp_tile" / "seed_stitch.pyp", 6);
  for (const std::string chart : {"plain", "basket2x2", "twill2x2", "kp/pk", "k/p", "kkpp", "110/011/101"})
    write_text(out / "tile_charts" / (chart == "k/p" ? "garter" : chart == "kp/pk" ? "seed" : chart == "110/011/101" ? "drawn" : chart), chart);

  // Tensile exports: header lines, three delimiters, a width column.
  write_text(out / "tensile_import" / "comma", std::string("\x00", 1) + "Instron export\nSpecimen 1\n"
             "Extension (mm),Load (N)\n0,0\n1,0.05\n2,0.12\n4,0.4\n8,1.6\n6,1.1\n");
  write_text(out / "tensile_import" / "semicolon_mm_width", std::string("\x03", 1) + "extension;force;width\n"
             "0;0;50\n10;2;48.5\n20;6;46\n30;15;43\n");
  write_text(out / "tensile_import" / "tab_cN_loading", std::string("\x0c", 1) + "stretch\tforce\n0\t0\n0.1\t30\n"
             "0.2\t90\n0.3\t220\n0.25\t150\n");

  // Yarn parameters and uniform targets, by the project's writers.
  const yarn::ParameterScales scales{400.0, 2e-4};
  const auto params = yarn::default_params(scales);
  write_text(out / "yarn_params" / "params.json", yarn::to_json(params).dump(2));
  {
    std::ostringstream yaml;
    const nlohmann::json j = yarn::to_json(params);
    for (const auto& [key, value] : j.items()) yaml << key << ": " << value.dump() << "\n";
    write_text(out / "yarn_params" / "params.yaml", yaml.str());
  }
  write_text(out / "yarn_params" / "partial.yaml", "ks1: 12\neps_s: 0.005\nkb: 1e-8\nR1: 2e-4\nkc1: 9e5\n");
  std::vector<db::DirectionTargets> targets;
  for (const auto d : {db::Direction::weft, db::Direction::bias, db::Direction::warp}) {
    db::DirectionTargets t;
    t.direction = d;
    for (int i = 0; i < 6; ++i) t.stretch.push_back({0.05 * i, -0.01 * i, 3.0 * i * i, true});
    for (int i = 0; i < 3; ++i) t.bending.push_back({10.0 * i, 1e-6 * i});
    targets.push_back(t);
  }
  write_text(out / "uniform_targets" / "targets.csv", db::uniform_targets_csv(targets));

  // Result files yarnfit wrote (version 1), and the same read and written at this version.
  const fs::path results = source / "tests/results/data";
  const nlohmann::json shell = nlohmann::json::parse(read_text(results / "shell_fit_v1.json"));
  const nlohmann::json yarn_fit = nlohmann::json::parse(read_text(results / "yarn_fit_v1.json"));
  const nlohmann::json tile = nlohmann::json::parse(read_text(results / "tile_v1.json"));
  write_text(out / "shell_fit_file" / "v1.json", shell.dump());
  write_text(out / "shell_fit_file" / "current.json", results::to_json(results::shell_fit_file_from_json(shell)).dump());
  write_text(out / "yarn_fit_file" / "v1.json", yarn_fit.dump());
  write_text(out / "yarn_fit_file" / "current.json", results::to_json(results::yarn_fit_file_from_json(yarn_fit)).dump());
  write_text(out / "tile_file" / "v1.json", tile.dump());
  write_text(out / "tile_file" / "current.json", results::to_json(results::tile_file_from_json(tile)).dump());

  // Checkpoints, by their writers.
  {
    yarn::FitCheckpoint c;
    Eigen::VectorXd point(5);
    point << 12.0, 0.005, 1e-8, 2e-4, 9e5;
    c.rescored = std::vector<yarn::GlobalCandidate>{{point, 0.25}, {point * 1.1, 0.5}};
    c.local = {yarn::AlternationSummary{}, std::nullopt};
    fs::create_directories(out / "fit_checkpoint");
    yarn::write_fit_checkpoint(out / "fit_checkpoint" / "two_starts.json", c);
  }
  {
    const swarm::ParameterSpace space({{"ks1", 0.4, 400.0, true},
                                       {"eps_s", 1e-4, 0.15, true},
                                       {"kb", 1e-9, 1e-5, true},
                                       {"R1", 1e-4, 3e-4, false},
                                       {"kc1", 1e3, 1e7, true}});
    swarm::detail::SwarmState s;
    s.settings.particles = 4;
    s.settings.iterations = 3;
    s.iterations_done = 1;
    s.position = Eigen::MatrixXd::Constant(5, 4, 0.25);
    s.velocity = Eigen::MatrixXd::Constant(5, 4, 0.01);
    s.best_position = s.position;
    s.best_value = Eigen::VectorXd::Constant(4, 0.5);
    s.global_best = s.position.col(0);
    fs::create_directories(out / "swarm_checkpoint");
    swarm::detail::write_checkpoint(out / "swarm_checkpoint" / "stage.json", space, s);
  }

  // Fit requests as the service documents them.
  write_text(out / "fit_request" / "quick", R"({"stages": "all", "budget": "quick", "seed": 7, "report": true})");
  write_text(out / "fit_request" / "shell", R"({"stages": "shell", "shell_model": "orthotropic", "max_iterations": 50})");
  write_text(out / "fit_request" / "search", R"({"particles": 16, "iterations": 4, "samples": 5, "local_samples": 8,)"
             R"( "local_evaluations": 40, "starts": 2, "global_method": "swarm", "local_method": "cobyla",)"
             R"( "no_profile": true, "fab_held_out": ["S1", "U1"]})");

  // FAB physics files: the public examples, thinned to every 25th sample.
  for (const std::string name : {"cupro_physics.json", "shirley_knit_physics.json"}) {
    nlohmann::json fab = nlohmann::json::parse(read_text(source / "tests/data/fab" / name));
    thin(fab, 25);
    write_text(out / "fab_physics" / name, fab.dump());
  }
  std::cout << "seeds written under " << out.string() << "\n";
  return 0;
}
