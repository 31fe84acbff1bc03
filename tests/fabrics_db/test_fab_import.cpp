// yarnfit db import-fab (issue 51): U3M 1.1 FAB physics read in SI units, written as a record
// that reads back, and every malformed file refused with its JSON path and nothing written.
#include <archive.h>
#include <archive_entry.h>

#include <cmath>
#include <functional>
#include <memory>

#include <nlohmann/json.hpp>

#include "fabrics_db/fab/fab_curves.hpp"
#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/fab/fab_physics.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

using json = nlohmann::json;

fs::path fab_data(const std::string& name) { return fs::path(YARNFIT_SOURCE_DIR) / "tests/data/fab" / name; }

// A small physics file with known numbers: every test at its nominal distance, two cycles,
// forces linear in the distance past a taut length of nominal + 0.1 cm, on a zero of z gf.
json synthetic_physics(double zero_gf = -1.5) {
  json raw = json::object();
  for (const char* grain : {"L", "W", "B"}) {
    json g = json::object();
    for (const auto& spec : db::k_fab_tests) {
      const double d0 = spec.nominal_distance * 100.0;  // cm
      const double taut = d0 + 0.1;
      json tree = json::array();
      for (int cycle = 1; cycle <= 2; ++cycle) {
        json loading = json::array(), relaxation = json::array();
        for (int k = 0; k <= 10; ++k) {
          const double d = spec.kind == db::FabTestKind::stretch ? d0 + 0.05 * cycle * k : d0 - 0.02 * cycle * k;
          const double f = zero_gf + (d > taut ? 100.0 * (d - taut) : 0.0);
          loading.push_back(d);
          loading.push_back(f);
        }
        for (int k = 10; k >= 0; --k) {
          relaxation.push_back(loading[2 * static_cast<std::size_t>(k)]);
          relaxation.push_back(loading[2 * static_cast<std::size_t>(k) + 1]);
        }
        tree.push_back(loading);
        tree.push_back(relaxation);
      }
      g[spec.name] = {{"freq", 55},        {"width", 5},         {"length", taut},   {"samplesTree", tree},
                      {"hwSerialNumber", 7}, {"hwVersion", 1}, {"testVersion", 15}, {"time", 1580128950}};
    }
    raw[grain] = g;
  }
  raw["M"] = 120.0;
  raw["T"] = {{"freq", 55}, {"width", 5}, {"samplesTree", json::array({json::array({0.025, -500.0, 0.02, -900.0})})},
              {"hwSerialNumber", 7}, {"hwVersion", 1}, {"testVersion", 15}, {"time", 1580128759}};
  return {{"schema", "1.1"}, {"raw_data", raw}, {"custom", {{"browzwear", {{"name", "Test twill"}, {"category", "Weaves"}}}}}};
}

db::FabImportOptions options(const fs::path& in, const fs::path& out) {
  db::FabImportOptions o;
  o.input = in;
  o.output = out;
  o.denier = 150.0;
  return o;
}

const db::FabTest& test_of(const db::FabMeasurement& m, db::Direction d, const std::string& name) {
  for (const auto& t : m.tests.at(d))
    if (t.name == name) return t;
  throw std::runtime_error("no test " + name);
}

TEST(FabImport, ReadsThePublicCuproInSiUnits) {
  const auto r = db::read_fab_file(fab_data("cupro_physics.json"));
  ASSERT_TRUE(r.measurement) << r.problems.to_string();
  const auto& m = *r.measurement;
  ASSERT_EQ(m.tests.size(), 3u);
  for (const auto& [d, tests] : m.tests) {
    ASSERT_EQ(tests.size(), 5u);
    for (const auto& t : tests) EXPECT_EQ(t.branches.size(), t.kind == db::FabTestKind::stretch ? 8u : 6u) << t.name;
  }
  EXPECT_NEAR(m.mass_per_area, 0.1056, 1e-6);
  // The FAB's thickness figure (custom block, in mm) is the thickness test's first contact.
  EXPECT_NEAR(*m.thickness, 0.10464175045490265e-3, 1e-11);  // the custom block's figure, in single precision
  EXPECT_EQ(*m.serial, 212544);
  EXPECT_EQ(m.name, "SU-1098 Cupro");
  EXPECT_EQ(m.composition, "Rayon 100 %");
  // Length grain → warp; its 8 cm stretch from the file's `length`, 8.128 cm; 5 cm wide.
  const auto& s2 = test_of(m, db::Direction::warp, "S2");
  EXPECT_NEAR(s2.clamp_distance, 0.08127973556518555, 1e-12);
  EXPECT_DOUBLE_EQ(s2.strip_width, 0.05);
  EXPECT_NEAR(s2.branches[0].clamp_distance[0], 0.07978235721588135, 1e-12);
  EXPECT_NEAR(s2.branches[0].raw_force[0], 0.6588166356086731 * 9.80665e-3, 1e-12);
  EXPECT_EQ(s2.branches[1].branch, db::FabBranch::relaxation);
  EXPECT_EQ(s2.branches[7].cycle, 4);
  // The 2 cm stretch reads about −2 gf while the strip is slack: the load cell's zero.
  const auto& s1 = test_of(m, db::Direction::warp, "S1");
  ASSERT_TRUE(s1.zero_offset);
  EXPECT_GT(*s1.zero_offset, -2.6 * db::k_gram_force);
  EXPECT_LT(*s1.zero_offset, -1.5 * db::k_gram_force);
  EXPECT_GE(s1.zero_offset_samples, 10);
  // A bend's strip is looped from its first sample: no zero is claimed for it.
  EXPECT_FALSE(test_of(m, db::Direction::warp, "U1").zero_offset);
}

TEST(FabImport, ReadsThePublicKnit) {
  const auto r = db::read_fab_file(fab_data("shirley_knit_physics.json"));
  ASSERT_TRUE(r.measurement) << r.problems.to_string();
  EXPECT_NEAR(r.measurement->mass_per_area, 0.3, 1e-9);
  EXPECT_NEAR(*r.measurement->thickness, 0.20203916728496552e-3, 2e-9);  // custom: 0.202039 mm
  EXPECT_EQ(test_of(*r.measurement, db::Direction::bias, "D2").branches.size(), 6u);
}

TEST(FabImport, ConvertsUnitsExactlyAndEstimatesTheZero) {
  ScratchDir dir("fab");
  write_file(dir / "p.json", synthetic_physics(-1.5).dump());
  const auto r = db::read_fab_file(dir / "p.json");
  ASSERT_TRUE(r.measurement) << r.problems.to_string();
  const auto& s2 = test_of(*r.measurement, db::Direction::weft, "S2");
  EXPECT_DOUBLE_EQ(s2.clamp_distance, 8.1 * 0.01);
  EXPECT_DOUBLE_EQ(s2.branches[0].raw_force[0], -1.5 * 9.80665e-3);
  ASSERT_TRUE(s2.zero_offset);
  EXPECT_DOUBLE_EQ(*s2.zero_offset, -1.5 * 9.80665e-3);
  // The stretch curve: taut length on, zero taken off, 100 gf/cm past it.
  int dropped = 0;
  const auto c = db::fab_stretch_curve(s2, dropped);
  ASSERT_GE(c.size(), 5u);
  EXPECT_EQ(dropped, 0);
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_NEAR(c.force[i], 100.0 * c.stretch[i] * 8.1 * 9.80665e-3, 1e-9) << i;
}

TEST(FabImport, WritesARecordThatReadsBackWithEverySample) {
  ScratchDir dir("fab");
  const auto r = db::import_fab(options(fab_data("cupro_physics.json"), dir / "cupro"));
  ASSERT_TRUE(r.written) << r.problems.to_string();
  const auto load = db::load_fabric(dir / "cupro");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const db::Fabric& f = *load.fabric;
  EXPECT_EQ(f.id, "cupro");
  EXPECT_EQ(f.family, "weaves");
  EXPECT_NEAR(*f.areal_density, 0.1055999984741211, 1e-15);  // M as the file gives it
  EXPECT_EQ(f.yarns.at(0).material, "Rayon 100 %");
  EXPECT_EQ(f.stretch_tests.size(), 3u);
  EXPECT_NEAR(f.stretch_tests.at(db::Direction::warp).swatch.length, 0.08127973556518555, 1e-12);
  // Every sample of every test (forces bit for bit; distances through millimetres, to the last
  // bit), and the physics file unchanged.
  const auto& m = *r.measurement;
  for (const auto& [d, tests] : m.tests) {
    ASSERT_EQ(f.fab_tests.at(d).size(), tests.size());
    for (std::size_t i = 0; i < tests.size(); ++i) {
      const auto& a = tests[i];
      const auto& b = f.fab_tests.at(d)[i];
      EXPECT_EQ(a.name, b.name);
      EXPECT_DOUBLE_EQ(a.clamp_distance, b.clamp_distance);
      EXPECT_EQ(a.zero_offset.has_value(), b.zero_offset.has_value());
      if (a.zero_offset) {
        EXPECT_DOUBLE_EQ(*a.zero_offset, *b.zero_offset);
      }
      ASSERT_EQ(a.branches.size(), b.branches.size());
      for (std::size_t k = 0; k < a.branches.size(); ++k) {
        EXPECT_EQ(a.branches[k].cycle, b.branches[k].cycle);
        EXPECT_EQ(a.branches[k].branch, b.branches[k].branch);
        EXPECT_EQ(a.branches[k].raw_force, b.branches[k].raw_force);
        for (std::size_t j = 0; j < a.branches[k].clamp_distance.size(); ++j)
          EXPECT_NEAR(a.branches[k].clamp_distance[j], b.branches[k].clamp_distance[j], 1e-15 * a.branches[k].clamp_distance[j]);
      }
    }
  }
  EXPECT_EQ(read_file(dir / "cupro/fab/physics.json"), read_file(fab_data("cupro_physics.json")));
  EXPECT_EQ(*f.fab_source->serial, 212544);
}

TEST(FabImport, NeverOverwritesAndNeedsTheDenier) {
  ScratchDir dir("fab");
  fs::create_directories(dir / "taken");
  write_file(dir / "taken/keep.txt", "mine");
  auto r = db::import_fab(options(fab_data("cupro_physics.json"), dir / "taken"));
  EXPECT_FALSE(r.written);
  EXPECT_TRUE(contains(r.problems.to_string(), "already exists")) << r.problems.to_string();
  EXPECT_EQ(read_file(dir / "taken/keep.txt"), "mine");
  auto o = options(fab_data("cupro_physics.json"), dir / "new");
  o.denier.reset();
  r = db::import_fab(o);
  EXPECT_FALSE(r.written);
  EXPECT_TRUE(contains(r.problems.to_string(), "denier")) << r.problems.to_string();
  EXPECT_FALSE(fs::exists(dir / "new"));
}

// Each broken file: refused, its JSON path named, nothing written (no folder, no staging left).
struct Broken {
  const char* what;
  std::function<void(json&)> edit;
  const char* path;
};

TEST(FabImport, RefusesEachBrokenFileNamingItsJsonPath) {
  const std::vector<Broken> cases{
      {"a grain missing", [](json& j) { j["raw_data"].erase("W"); }, "/raw_data/W"},
      {"a test missing", [](json& j) { j["raw_data"]["L"].erase("D2"); }, "/raw_data/L/D2"},
      {"odd-length samples", [](json& j) { j["raw_data"]["B"]["S1"]["samplesTree"][2].erase(3); },
       "/raw_data/B/S1/samplesTree/2"},
      {"odd number of branches", [](json& j) { j["raw_data"]["B"]["U1"]["samplesTree"].erase(3); },
       "/raw_data/B/U1/samplesTree"},
      {"a negative width", [](json& j) { j["raw_data"]["W"]["U1"]["width"] = -5; }, "/raw_data/W/U1/width"},
      {"a number as text", [](json& j) { j["raw_data"]["L"]["S1"]["length"] = "2.1"; }, "/raw_data/L/S1/length"},
      {"a sample as text", [](json& j) { j["raw_data"]["L"]["S2"]["samplesTree"][1][5] = "0.3"; },
       "/raw_data/L/S2/samplesTree/1/5"},
      {"the mass missing", [](json& j) { j["raw_data"].erase("M"); }, "/raw_data/M"},
      {"no raw data", [](json& j) { j["raw_data"] = nullptr; }, "/raw_data"},
      {"a wrong schema", [](json& j) { j["schema"] = "1.0"; }, "/schema"},
      {"a 2 cm distance on an 8 cm test", [](json& j) { j["raw_data"]["W"]["S2"]["length"] = 2.1; },
       "/raw_data/W/S2/length"},
      {"a serial beyond a double's whole numbers", [](json& j) { j["raw_data"]["L"]["S1"]["hwSerialNumber"] = 18446744073709551615ULL; },
       "/raw_data/L/S1/hwSerialNumber"},
      {"a sampling rate past int", [](json& j) { j["raw_data"]["L"]["U1"]["freq"] = 3000000000LL; }, "/raw_data/L/U1/freq"},
      {"a time after 2100", [](json& j) { j["raw_data"]["B"]["D1"]["time"] = 1000000000000000LL; }, "/raw_data/B/D1/time"},
  };
  for (const auto& c : cases) {
    ScratchDir dir("fab");
    json j = synthetic_physics();
    c.edit(j);
    write_file(dir / "p.json", j.dump());
    const auto r = db::import_fab(options(dir / "p.json", dir / "record"));
    EXPECT_FALSE(r.written) << c.what;
    EXPECT_TRUE(contains(r.problems.to_string(), (dir / "p.json").string() + ": " + c.path + ":"))
        << c.what << ":\n" << r.problems.to_string();
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1) << c.what;
  }
}

TEST(FabImport, NamesThePathAndLineOfANaN) {
  ScratchDir dir("fab");
  std::string text = synthetic_physics().dump(1);
  // Writers such as Python's json put a bare NaN where a number failed.
  const std::string target = "\"samplesTree\":";
  const auto at = text.find("[", text.find(target, text.find("\"S2\"", text.find("\"L\""))));  // L/S2's first list
  const auto first = text.find("[", at + 1);
  const auto comma = text.find(",", first);
  text.replace(first + 1, comma - first - 1, "NaN");
  write_file(dir / "p.json", text);
  const auto r = db::import_fab(options(dir / "p.json", dir / "record"));
  EXPECT_FALSE(r.written);
  const std::string p = r.problems.to_string();
  EXPECT_TRUE(contains(p, "/raw_data/L/S2/samplesTree/0/0")) << p;
  EXPECT_TRUE(contains(p, "NaN")) << p;
  EXPECT_FALSE(fs::exists(dir / "record"));
}

TEST(FabImport, NamesTheSyntaxOfAnOverflowAndAnyDepth) {
  ScratchDir dir("fab");
  std::string text = synthetic_physics().dump();
  text.replace(text.find("\"M\":120.0"), 9, "\"M\":1e309");
  write_file(dir / "big.json", text);
  auto r = db::import_fab(options(dir / "big.json", dir / "record"));
  EXPECT_FALSE(r.written);
  EXPECT_TRUE(contains(r.problems.to_string(), "/raw_data/M: malformed JSON (number overflow parsing '1e309')"))
      << r.problems.to_string();
  // A schema nested a hundred thousand deep: refused in a line, without recursing through it.
  write_file(dir / "deep.json", "{\"schema\":" + std::string(100000, '[') + std::string(100000, ']') + "}");
  r = db::import_fab(options(dir / "deep.json", dir / "record"));
  EXPECT_FALSE(r.written);
  EXPECT_TRUE(contains(r.problems.to_string(), "/schema: expected \"1.1\" (U3M 1.1 physics), got a list"))
      << r.problems.to_string().substr(0, 300);
  EXPECT_FALSE(fs::exists(dir / "record"));
}

TEST(FabImport, DefaultsItsIdAndFamilyOrSaysWhy) {
  ScratchDir dir("fab");
  json j = synthetic_physics();
  j["custom"]["browzwear"]["category"] = "ニット";  // no letter an id may use: the family falls back
  write_file(dir / "p.json", j.dump());
  auto r = db::import_fab(options(dir / "p.json", dir / "knit/"));
  ASSERT_TRUE(r.written) << r.problems.to_string();
  EXPECT_EQ(db::load_fabric(dir / "knit").fabric->family, "fab");
  r = db::import_fab(options(dir / "p.json", dir / "My Fabric"));
  EXPECT_FALSE(r.written);
  EXPECT_TRUE(contains(r.problems.to_string(), "id: 'My Fabric' is not a record id")) << r.problems.to_string();
  EXPECT_FALSE(fs::exists(dir / "My Fabric"));
}

// A .u3m names its physics file; a .u3ma holds both.
std::string zip_of(const std::vector<std::pair<std::string, std::string>>& files) {
  std::string out;
  std::unique_ptr<archive, int (*)(archive*)> a(archive_write_new(), archive_write_free);
  archive_write_set_format_zip(a.get());
  archive_write_open2(
      a.get(), &out, nullptr,
      [](archive*, void* data, const void* buf, std::size_t n) -> la_ssize_t {
        static_cast<std::string*>(data)->append(static_cast<const char*>(buf), n);
        return static_cast<la_ssize_t>(n);
      },
      nullptr, nullptr);
  for (const auto& [name, text] : files) {
    std::unique_ptr<archive_entry, void (*)(archive_entry*)> e(archive_entry_new(), archive_entry_free);
    archive_entry_set_pathname(e.get(), name.c_str());
    archive_entry_set_filetype(e.get(), AE_IFREG);
    archive_entry_set_perm(e.get(), 0644);
    archive_entry_set_size(e.get(), static_cast<la_int64_t>(text.size()));
    archive_write_header(a.get(), e.get());
    archive_write_data(a.get(), text.data(), text.size());
  }
  archive_write_close(a.get());
  return out;
}

TEST(FabImport, ReadsAU3mAndAU3maNamingThePhysics) {
  ScratchDir dir("fab");
  const json material = {{"schema", "1.1"},
                         {"material", {{"name", "t"}, {"physics", {{"devices", {{"fab", "physics/physics.json"}}}}}}}};
  const std::string physics = synthetic_physics().dump();
  fs::create_directories(dir / "m/physics");
  write_file(dir / "m/t.u3m", material.dump());
  write_file(dir / "m/physics/physics.json", physics);
  const auto a = db::read_fab_file(dir / "m/t.u3m");
  ASSERT_TRUE(a.measurement) << a.problems.to_string();
  write_file(dir / "t.u3ma", zip_of({{"t.u3m", material.dump()}, {"physics/physics.json", physics}}));
  const auto b = db::read_fab_file(dir / "t.u3ma");
  ASSERT_TRUE(b.measurement) << b.problems.to_string();
  EXPECT_EQ(b.measurement->physics_text, physics);
  // A material whose physics path leaves its folder is refused, not followed.
  json outside = material;
  outside["material"]["physics"]["devices"]["fab"] = "../p.json";
  write_file(dir / "m/out.u3m", outside.dump());
  write_file(dir / "p.json", physics);
  const auto c = db::read_fab_file(dir / "m/out.u3m");
  EXPECT_FALSE(c.measurement);
  EXPECT_TRUE(contains(c.problems.to_string(), "/material/physics/devices/fab")) << c.problems.to_string();
  // A material naming itself is read as physics once, not followed round.
  json self = material;
  self["material"]["physics"]["devices"]["fab"] = "self.u3m";
  write_file(dir / "m/self.u3m", self.dump());
  const auto e = db::read_fab_file(dir / "m/self.u3m");
  EXPECT_FALSE(e.measurement);
  EXPECT_TRUE(contains(e.problems.to_string(), "/raw_data: missing")) << e.problems.to_string();
  // A folder is not a file.
  EXPECT_TRUE(contains(db::read_fab_file(dir / "m").problems.to_string(), "not a regular file"));
}

TEST(FabImport, TheRecordReaderChecksFabTests) {
  ScratchDir dir("fab");
  ASSERT_TRUE(db::import_fab(options(fab_data("cupro_physics.json"), dir / "r")).written);
  std::string yaml = read_file(dir / "r/fabric.yaml");
  yaml.replace(yaml.find("    D2:"), 7, "    D3:");
  write_file(dir / "r/fabric.yaml", yaml);
  std::string csv = read_file(dir / "r/fab/weft_S1.csv");
  csv.replace(csv.find(",loading,"), 9, ",load,");
  write_file(dir / "r/fab/weft_S1.csv", csv);
  const auto load = db::load_fabric(dir / "r");
  const std::string p = load.problems.to_string();
  EXPECT_FALSE(load.ok());
  EXPECT_TRUE(contains(p, "fab_tests.weft.D3: unknown FAB test")) << p;
  EXPECT_TRUE(contains(p, "weft_S1.csv:2: branch: 'load': expected loading or relaxation")) << p;
}

TEST(FabImport, CommandExitsTwoAndWritesNothingOnABrokenFile) {
  ScratchDir dir("fab");
  json j = synthetic_physics();
  j["raw_data"]["L"]["S2"]["samplesTree"][0][3] = "1.0";
  write_file(dir / "p.json", j.dump());
  auto r = run_cli("db import-fab " + quoted(dir / "p.json") + " --out " + quoted(dir / "rec") + " --denier 150");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(contains(r.err, "/raw_data/L/S2/samplesTree/0/3")) << r.err;
  EXPECT_FALSE(fs::exists(dir / "rec"));
  r = run_cli("db import-fab " + quoted(fab_data("cupro_physics.json")) + " --out " + quoted(dir / "cupro") +
              " --denier 150");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "15 FAB tests (102 branches)")) << r.out;
  EXPECT_EQ(run_cli("db validate " + quoted(dir / "cupro")).exit_code, 0);
}

}  // namespace
}  // namespace yarnfit::testing
