// yarnfit yarn sim / yarn curve on the real stockinette tile of ../shared (issue 4 "Command"):
// the JSON names of SPEC §5 and their values against the library called directly, free
// against fixed compression, a stretch curve, the OBJ dump, failures that still report, and
// invalid input (exit 2 naming the file or option).
#include <nlohmann/json.hpp>

#include <cmath>
#include <set>
#include <sstream>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"

namespace yarnfit::testing {
namespace {

using nlohmann::json;


double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

class YarnCli : public ::testing::Test {
 protected:
  void SetUp() override {
    YARNFIT_REQUIRE_SHARED(shared_stockinette());
    db::Problems problems;
    auto read = db::read_pyp(shared_stockinette(), problems);
    ASSERT_TRUE(read) << problems.to_string();
    tile = *read;
    params = yarn::default_params({400.0, db::compute_tile_facts(tile).r_est});
    write_file(params_file(), yarn::to_json(params).dump(2) + "\n");  // JSON is YAML
  }
  [[nodiscard]] fs::path params_file() const { return dir / "yarn_params.yaml"; }
  [[nodiscard]] std::string scene_args() const {
    return "--pattern " + quoted(shared_stockinette()) + " --params " + quoted(params_file());
  }
  // The state `yarn sim` starts from: the rest-shape heuristic with its default options.
  yarn::YarnSystem relaxed_system(Eigen::VectorXd& g) const {
    yarn::YarnSystem sys(yarn::make_yarn_tile(tile), params);
    g = Eigen::VectorXd::Zero(sys.dof_count());
    yarn::relax_rest_shape(sys, g);
    return sys;
  }

  ScratchDir dir{"yarncli"};
  db::PeriodicTile tile;
  yarn::YarnParams params;
};

json parse_json(const CommandResult& r) {
  json j = json::parse(r.out, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << "not JSON:\n" << r.out << r.err;
  return j;
}

TEST_F(YarnCli, SimPrintsTheSpecifiedFieldsAndMatchesTheLibrary) {
  const auto r = run_cli("yarn sim " + scene_args() + " --direction weft --stretch 0.3 --compression 0 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const json j = parse_json(r);
  for (const char* k : {"energy_density", "stress_s", "compression", "converged", "newton_iterations", "seconds", "effects"})
    EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_TRUE(j["converged"].get<bool>());
  const std::string termination = j["termination"];
  EXPECT_TRUE(termination == "converged" || termination == "converged_readout") << termination;
  EXPECT_EQ(j["effects"], json({"stretch", "bending", "contact"}));
  EXPECT_TRUE(j["rest_shape"]["applied"].get<bool>());
  EXPECT_EQ(j["params"], yarn::to_json(params));

  Eigen::VectorXd g;
  yarn::YarnSystem sys = relaxed_system(g);
  const yarn::Sample s = yarn::simulate_sample(sys, {0.3, 0.0, 0.0, yarn::weft_angle()}, g);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_LT(rel(j["energy_density"].get<double>(), s.energy_density), 1e-12);
  EXPECT_LT(rel(j["stress_s"].get<double>(), s.stress_s), 1e-12);
  EXPECT_LT(rel(j["stress_c"].get<double>(), s.stress_c), 1e-12);
  EXPECT_EQ(j["compression"].get<double>(), 0.0);
  EXPECT_EQ(j["newton_iterations"].get<int>(), s.newton_iterations);
  EXPECT_GT(j["stress_s"].get<double>(), 0.0);
}

TEST_F(YarnCli, FreeCompressionAgreesWithTheLibraryAndWithTheFixedCompressionItFound) {
  // Without the rest shape (tested above) to keep the test short.
  const std::string args = scene_args() + " --no-rest-shape --direction weft --stretch 0.2";
  const auto r = run_cli("yarn sim " + args + " --free-compression --json");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const json free = parse_json(r);
  ASSERT_TRUE(free["converged"].get<bool>());
  EXPECT_EQ(free["compression_mode"], "free");
  EXPECT_FALSE(free["rest_shape"]["applied"].get<bool>());
  const double c = free["compression"].get<double>();
  const double sigma = free["stress_s"].get<double>();
  EXPECT_LT(std::abs(free["stress_c"].get<double>()), 1e-3 * std::abs(sigma));

  yarn::YarnSystem sys(yarn::make_yarn_tile(tile), params);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(sys.dof_count());
  const yarn::Sample s = yarn::solve_free_compression(sys, {0.2, 0.0, 0.0, yarn::weft_angle()}, g);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_LT(rel(c, s.chi.compression), 1e-12);
  EXPECT_LT(rel(sigma, s.stress_s), 1e-12);
  EXPECT_LT(rel(free["energy_density"].get<double>(), s.energy_density), 1e-12);
  EXPECT_EQ(free["solves"].get<int>(), s.solves);
  EXPECT_EQ(free["newton_iterations"].get<int>(), s.newton_iterations);

  // The same compression given explicitly: the same state, zero orthogonal stress.
  std::ostringstream cs;
  cs.precision(17);
  cs << c;
  const auto f = run_cli("yarn sim " + args + " --compression " + cs.str() + " --json");
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const json fixed = parse_json(f);
  EXPECT_EQ(fixed["compression_mode"], "fixed");
  EXPECT_LT(rel(fixed["energy_density"].get<double>(), free["energy_density"].get<double>()), 1e-9);
  EXPECT_LT(rel(fixed["stress_s"].get<double>(), sigma), 1e-9);
  EXPECT_LT(std::abs(fixed["stress_c"].get<double>()), 1e-3 * std::abs(sigma));
}

// Rows of a CSV with a header, as strings.
std::vector<std::vector<std::string>> csv_cells(const std::string& text, std::vector<std::string>& header) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    if (header.empty()) header = cells;
    else rows.push_back(cells);
  }
  return rows;
}

// Counts of an OBJ file: vertices, polylines and the segments they hold; every index valid.
struct ObjCounts {
  int vertices = 0, polylines = 0, segments = 0, objects = 0;
  bool indices_valid = true, finite = true;
};
ObjCounts read_obj(const fs::path& file) {
  ObjCounts c;
  std::istringstream in(read_file(file));
  std::string line;
  std::vector<int> indices;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      double x = NAN, y = NAN, z = NAN;
      ls >> x >> y >> z;
      c.finite = c.finite && std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
      ++c.vertices;
    } else if (tag == "l") {
      int n = 0;
      for (int i = 0; ls >> i; ++n) indices.push_back(i);
      ++c.polylines;
      c.segments += n - 1;
    } else if (tag == "o") {
      ++c.objects;
    }
  }
  for (int i : indices) c.indices_valid = c.indices_valid && i >= 1 && i <= c.vertices;
  return c;
}

TEST_F(YarnCli, CurveWritesAMonotoneWeftCurveAndOneObjPerPoint) {
  // 0–30 % in four points keeps the test short (about 3 s on 2 cores).
  const auto r = run_cli("yarn curve " + scene_args() + " --direction weft --max-stretch 0.3 --points 4 --out " +
                         quoted(dir / "out" / "weft.csv") + " --dump-dir " + quoted(dir / "states"));
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  std::vector<std::string> header;
  const auto rows = csv_cells(read_file(dir / "out" / "weft.csv"), header);
  const std::vector<std::string> expected{"direction", "stretch", "compression", "energy_density_J_per_m2",
                                          "stress_s_N_per_m", "converged", "newton_iterations", "seconds"};
  ASSERT_GE(header.size(), expected.size());
  EXPECT_EQ(std::vector<std::string>(header.begin(), header.begin() + 8), expected);
  ASSERT_EQ(rows.size(), 4u);
  double previous_stress = -1e300, previous_psi = -1e300;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][0], "weft");
    EXPECT_NEAR(std::stod(rows[i][1]), 0.1 * static_cast<double>(i), 1e-12);
    ASSERT_EQ(rows[i][5], "1") << "point " << i << " did not converge: " << rows[i].back();
    const double stress = std::stod(rows[i][4]), psi = std::stod(rows[i][3]);
    EXPECT_GT(stress, previous_stress) << "s = " << rows[i][1];
    EXPECT_GT(psi, previous_psi) << "s = " << rows[i][1];
    previous_stress = stress;
    previous_psi = psi;
  }
  // The rest shape leaves the tile nearly stress-free at rest (the library's own test holds
  // it to 5 % of the 10 % stress; here the rest compression is free as well).
  EXPECT_LT(std::abs(std::stod(rows[0][4])), 0.1 * std::stod(rows[1][4]));
  int dumps = 0;
  for (const auto& e : fs::directory_iterator(dir / "states")) {
    EXPECT_EQ(e.path().extension(), ".obj");
    EXPECT_EQ(read_obj(e.path()).segments, tile.edge_count()) << e.path();
    ++dumps;
  }
  EXPECT_EQ(dumps, 4);
}

TEST_F(YarnCli, DumpWritesOnePolylinePerYarnWithOneSegmentPerEdge) {
  const auto facts = db::compute_tile_facts(tile);
  int open_yarns = 0;
  for (const auto& y : facts.yarns) open_yarns += (y.offset_x != 0 || y.offset_y != 0) ? 1 : 0;
  const auto r = run_cli("yarn sim " + scene_args() + " --no-rest-shape --stretch 0.1 --dump " + quoted(dir / "t.obj") +
                         " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "--quiet without --json prints nothing: " << r.out;
  ObjCounts c = read_obj(dir / "t.obj");
  EXPECT_EQ(c.segments, tile.edge_count());
  EXPECT_EQ(c.polylines, static_cast<int>(facts.yarns.size()));
  EXPECT_EQ(c.vertices, tile.vertex_count() + open_yarns);
  EXPECT_TRUE(c.indices_valid && c.finite);

  const auto n = run_cli("yarn sim " + scene_args() + " --no-rest-shape --stretch 0.1 --dump " + quoted(dir / "n.obj") +
                         " --dump-neighbours -q");
  ASSERT_EQ(n.exit_code, 0) << n.err;
  c = read_obj(dir / "n.obj");
  EXPECT_EQ(c.objects, 9);
  EXPECT_EQ(c.segments, 9 * tile.edge_count());
  EXPECT_TRUE(c.indices_valid && c.finite);
}

TEST_F(YarnCli, UnconvergedSolvesStillReportTheirStatus) {
  // One Newton iteration cannot relax the tile: JSON with converged=false and the reason, exit 1.
  const auto r = run_cli("yarn sim " + scene_args() + " --no-rest-shape --stretch 0.3 --max-iterations 1 --json");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const json j = parse_json(r);
  EXPECT_FALSE(j["converged"].get<bool>());
  EXPECT_EQ(j["termination"], "max_iterations");
  EXPECT_TRUE(j["energy_density"].is_null());
  EXPECT_NE(r.err.find("not converged"), std::string::npos) << r.err;

  // A curve records each failed point and carries on.
  const auto c = run_cli("yarn curve " + scene_args() + " --no-rest-shape --max-stretch 0.1 --points 2 --max-iterations 1 -q --out " +
                         quoted(dir / "fail.csv"));
  EXPECT_EQ(c.exit_code, 1) << c.err;
  std::vector<std::string> header;
  const auto rows = csv_cells(read_file(dir / "fail.csv"), header);
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_EQ(row[5], "0");
    EXPECT_TRUE(row[4].empty()) << "no stress for a failed point";
  }
}

// Progress goes to a terminal only (SPEC §5): the point, the stretch, time and time left.
TEST_F(YarnCli, CurveShowsProgressOnATerminalOnly) {
  const std::string curve = "yarn curve " + scene_args() + " --no-rest-shape --max-stretch 0.05 --points 2 --out " +
                            quoted(dir / "p.csv");
  const auto r = run_cli(curve);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("point 1/2"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("2 of 2 points converged"), std::string::npos) << r.out;
  if (std::system("script --version >/dev/null 2>&1") != 0) GTEST_SKIP() << "no `script` to give the curve a terminal";
  const auto on_terminal = [&](const std::string& extra, const fs::path& log) {
    write_file(dir / "run.sh", quoted(YARNFIT_CLI) + " " + curve + extra + " >/dev/null\n");
    const std::string cmd = "script -qec " + quoted(fs::path("sh " + (dir / "run.sh").string())) + " " + quoted(log) +
                            " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    return read_file(log);
  };
  const std::string shown = on_terminal("", dir / "tty.log");
  EXPECT_NE(shown.find("\r\033[Kyarn curve weft: point 2/2, s = 0.05, "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s left"), std::string::npos) << shown;
  EXPECT_EQ(on_terminal(" --quiet", dir / "quiet.log").find("point 1/2"), std::string::npos);
}

TEST_F(YarnCli, InvalidInputExitsTwoNamingTheFileOrOption) {
  const std::string pattern = " --pattern " + quoted(shared_stockinette());
  const auto expect_invalid = [&](const std::string& args, const std::vector<std::string>& needles) {
    const auto r = run_cli("yarn sim " + args + " --stretch 0.1 --json");
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
    for (const auto& n : needles) EXPECT_NE(r.err.find(n), std::string::npos) << args << ": no '" << n << "' in\n" << r.err;
  };
  expect_invalid("--pattern " + quoted(dir / "missing.pyp") + " --params " + quoted(params_file()),
                 {(dir / "missing.pyp").string(), "file"});
  write_file(dir / "bad.pyp", "*pattern\n0.01 0.01 0.001 2\n*Q\n0 0 0 0\n");
  expect_invalid("--pattern " + quoted(dir / "bad.pyp") + " --params " + quoted(params_file()),
                 {(dir / "bad.pyp").string() + ":"});

  json p = yarn::to_json(params);
  p["ks_1"] = 1.0;
  write_file(dir / "typo.yaml", p.dump());
  expect_invalid(pattern + " --params " + quoted(dir / "typo.yaml"), {(dir / "typo.yaml").string() + ":", "ks_1"});
  p = yarn::to_json(params);
  p["R2"] = 2.0 * params.r1;
  write_file(dir / "r2.yaml", p.dump());
  expect_invalid(pattern + " --params " + quoted(dir / "r2.yaml"), {"r2.yaml", "R2: must be smaller than R1"});
  p = yarn::to_json(params);
  p.erase("kc2");
  write_file(dir / "no_kc2.yaml", p.dump());
  expect_invalid(pattern + " --params " + quoted(dir / "no_kc2.yaml"), {"no_kc2.yaml", "kc2: missing", "--ks2"});
  // With --ks2 the fixed parameter comes from the tile's scale instead.
  const auto ok = run_cli("yarn sim " + pattern + " --params " + quoted(dir / "no_kc2.yaml") +
                          " --ks2 400 --no-rest-shape --stretch 0 --max-iterations 1 --json");
  EXPECT_NE(ok.exit_code, 2) << ok.err;
  EXPECT_LT(rel(parse_json(ok)["params"]["kc2"].get<double>(), params.kc2), 1e-12);

  const std::string good = pattern + " --params " + quoted(params_file());
  const auto r = run_cli("yarn sim " + good + " --stretch -1.5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--stretch"), std::string::npos) << r.err;
  expect_invalid(good + " --compression 1.2", {"--compression"});
  expect_invalid(good + " --compression 0.1 --free-compression", {"--free-compression"});
  expect_invalid(good + " --direction diagonal", {"--direction"});
  const auto c = run_cli("yarn curve " + good + " --max-stretch 0 --out " + quoted(dir / "x.csv"));
  EXPECT_EQ(c.exit_code, 2);
  EXPECT_NE(c.err.find("--max-stretch"), std::string::npos) << c.err;
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
}

}  // namespace
}  // namespace yarnfit::testing
