// Every validation rule of fabric records, each with one broken input, checked through
// `yarnfit db validate`: exit code 2 and a stderr line naming the file, the line and the
// field (SPEC §2, §5).
#include <functional>
#include <map>
#include <sstream>

#include "fabrics_db/records/fabric_reader.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"

namespace yarnfit::testing {
namespace {

struct BrokenCase {
  std::string name;
  std::function<void(const fs::path&)> breaks;  // turns the valid base record into a bad one
  std::string expected;                         // "file:line: field: message start"
};

std::string expect_line(const std::string& file, int line, const std::string& rest) {
  return "/" + file + ":" + std::to_string(line) + ": " + rest;
}

std::vector<BrokenCase> broken_cases() {
  using P = const fs::path&;
  return {
      {"MalformedYaml", [](P d) { replace_in_file(d / "fabric.yaml", "family: test-family", "family: [unclosed"); },
       expect_line("fabric.yaml", 3, "yaml: malformed YAML")},
      {"YamlNotAMapping", [](P d) { write_file(d / "fabric.yaml", "- just\n- a list\n"); },
       expect_line("fabric.yaml", 1, "file: expected a mapping")},
      {"MissingRequiredKey", [](P d) { replace_in_file(d / "fabric.yaml", "family: test-family\n", ""); },
       expect_line("fabric.yaml", 1, "family: missing required key")},
      {"MissingYarnKey", [](P d) { replace_in_file(d / "fabric.yaml", "    denier: 20\n", ""); },
       expect_line("fabric.yaml", 11, "yarns[1].denier: missing required key")},
      {"UnknownTopLevelKey", [](P d) { replace_in_file(d / "fabric.yaml", "description:", "descripton:"); },
       expect_line("fabric.yaml", 3, "descripton: unknown key (did you mean 'description'?)")},
      {"UnknownNestedKey", [](P d) { replace_in_file(d / "fabric.yaml", "    file: stretch_warp.csv", "    file: stretch_warp.csv\n    fille: x"); },
       expect_line("fabric.yaml", 19, "stretch_tests.warp.fille: unknown key")},
      {"DuplicateKey", [](P d) { replace_in_file(d / "fabric.yaml", "family: test-family\n", "family: test-family\nfamily: other\n"); },
       expect_line("fabric.yaml", 3, "family: duplicate key")},
      {"UnknownStretchDirection", [](P d) { replace_in_file(d / "fabric.yaml", "  weft: {file: stretch_weft.csv}", "  wfet: {file: stretch_weft.csv}"); },
       expect_line("fabric.yaml", 16, "stretch_tests.wfet: unknown direction (did you mean 'weft'?)")},
      {"UnknownBendingDirection", [](P d) { replace_in_file(d / "fabric.yaml", "  weft: {file: bend_weft.csv}", "  diagonal: {file: bend_weft.csv}"); },
       expect_line("fabric.yaml", 22, "bending_tests.diagonal: unknown direction")},
      {"MissingCsvFile", [](P d) { fs::remove(d / "stretch_weft.csv"); },
       expect_line("fabric.yaml", 16, "stretch_tests.weft.file: cannot read")},
      {"UnreadableCsvFile", [](P d) { fs::remove(d / "stretch_warp.csv"); fs::create_directory(d / "stretch_warp.csv"); },
       expect_line("fabric.yaml", 18, "stretch_tests.warp.file: cannot read")},
      {"MissingBendingFile", [](P d) { fs::remove(d / "bend_weft.csv"); },
       expect_line("fabric.yaml", 22, "bending_tests.weft.file: cannot read")},
      {"MissingPatternFile", [](P d) { add_pattern_line(d, "{file: tile.pyp}"); },
       expect_line("fabric.yaml", 14, "pattern.file: cannot read")},
      {"UnreadablePattern", [](P d) {
         add_pattern_line(d, "{file: tile.pyp}");
         write_file(d / "tile.pyp", "*pattern # px py radius n\n0.001 0.001 0.0001 2\n\n*Q\n0 0 0 0\n0.0005 0 0 0\n\n*E\n0 7 0 0\n1 0 1 0\n");
       },
       expect_line("fabric.yaml", 14, "pattern.file: unreadable pattern")},
      {"PatternProblemNamesTileLine", [](P d) {
         add_pattern_line(d, "{file: tile.pyp}");
         write_file(d / "tile.pyp", "*pattern # px py radius n\n0.001 0.001 0.0001 2\n\n*Q\n0 0 0 0\n0.0005 0 0 0\n\n*E\n0 7 0 0\n1 0 1 0\n");
       },
       expect_line("tile.pyp", 9, "*E v1")},
      {"BadWeftAxis", [](P d) {
         add_pattern_line(d, "{file: tile.pyp, weft_axis: z}");
       },
       expect_line("fabric.yaml", 14, "pattern.weft_axis: expected x or y")},
      {"KnitUnknownChart", [](P d) {
         add_pattern_line(d, "{knit: stockinet, stitch_length_mm: 11, yarn_radius_mm: 0.7}");
       },
       expect_line("fabric.yaml", 14, "pattern.knit: unknown chart 'stockinet'")},
      {"KnitWithoutRadius", [](P d) {
         add_pattern_line(d, "{knit: seed, stitch_length_mm: 15}");
       },
       expect_line("fabric.yaml", 14, "pattern.yarn_radius_mm: missing required key")},
      {"KnitNegativeStitchLength", [](P d) {
         add_pattern_line(d, "{knit: kp/pk, stitch_length_mm: -1, yarn_radius_mm: 1}");
       },
       expect_line("fabric.yaml", 14, "pattern.stitch_length_mm: must be positive")},
      {"KnitAndFile", [](P d) {
         add_pattern_line(d, "{file: tile.pyp, knit: seed, stitch_length_mm: 15, yarn_radius_mm: 1}");
       },
       expect_line("fabric.yaml", 14, "pattern.knit: give either file")},
      {"StitchLengthWithoutKnit", [](P d) {
         add_pattern_line(d, "{file: tile.pyp, stitch_length_mm: 15}");
       },
       expect_line("fabric.yaml", 14, "pattern.stitch_length_mm: only with knit")},
      {"CsvMissingColumn", [](P d) { replace_in_file(d / "stretch_weft.csv", "stretch,force_N", "strech,force_N"); },
       expect_line("stretch_weft.csv", 1, "stretch: missing required column (did you mean 'strech'?)")},
      {"BendingCsvMissingColumn", [](P d) { replace_in_file(d / "bend_weft.csv", "aspect_ratio", "ratio"); },
       expect_line("bend_weft.csv", 1, "aspect_ratio: missing required column")},
      {"TextInNumericColumn", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.1,0.5,", "0.1,abc,"); },
       expect_line("stretch_weft.csv", 3, "force_N: expected a number, got 'abc'")},
      {"NaNInNumericColumn", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.1,0.5,", "0.1,NaN,"); },
       expect_line("stretch_weft.csv", 3, "force_N: NaN is not a valid value")},
      {"InfInNumericColumn", [](P d) { replace_in_file(d / "stretch_warp.csv", "0.2,1.2,0.05", "0.2,1.2,inf"); },
       expect_line("stretch_warp.csv", 4, "compression: infinite value")},
      {"EmptyCell", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.2,1.2,0.05", "0.2,,0.05"); },
       expect_line("stretch_weft.csv", 4, "force_N: missing value")},
      {"ShortRow", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.2,1.2,0.05", "0.2,1.2"); },
       expect_line("stretch_weft.csv", 4, "compression: missing value")},
      {"NegativeForce", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.1,0.5,", "0.1,-0.5,"); },
       expect_line("stretch_weft.csv", 3, "force_N: negative force")},
      {"StretchNotIncreasing", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.3,2.4", "0.15,2.4"); },
       expect_line("stretch_weft.csv", 5, "stretch: not strictly increasing: 0.15 follows 0.2 on line 4")},
      {"StretchRepeated", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.3,2.4", "0.2,2.4"); },
       expect_line("stretch_weft.csv", 5, "stretch: not strictly increasing")},
      {"ClampDistanceNotIncreasing", [](P d) { replace_in_file(d / "bend_weft.csv", "23,1.16", "2,1.16"); },
       expect_line("bend_weft.csv", 4, "clamp_distance_mm: not strictly increasing")},
      {"NonPositiveAspectRatio", [](P d) { replace_in_file(d / "bend_weft.csv", "13,1.25", "13,0"); },
       expect_line("bend_weft.csv", 3, "aspect_ratio: aspect ratio h/p must be positive")},
      {"CompressionBeyondOne", [](P d) { replace_in_file(d / "stretch_weft.csv", "0.3,2.4,0.08", "0.3,2.4,1.2"); },
       expect_line("stretch_weft.csv", 5, "compression: compression 1.2 would mean a width")},
      {"HeaderOnlyCsv", [](P d) { write_file(d / "stretch_weft.csv", "stretch,force_N,compression\n"); },
       expect_line("stretch_weft.csv", 1, "data: header only")},
      {"SingleRowCsv", [](P d) { write_file(d / "stretch_weft.csv", "stretch,force_N,compression\n0,0,0\n"); },
       expect_line("stretch_weft.csv", 2, "data: only 1 data row")},
      {"EmptyCsv", [](P d) { write_file(d / "stretch_weft.csv", "\n# nothing\n"); },
       "/stretch_weft.csv: header: no header line"},
      {"MassFractionsDoNotSumToOne", [](P d) { replace_in_file(d / "fabric.yaml", "    mass_fraction: 0.1", "    mass_fraction: 0.3"); },
       expect_line("fabric.yaml", 5, "yarns: mass fractions sum to 1.2, expected 1")},
      {"MassFractionAsPercent", [](P d) { replace_in_file(d / "fabric.yaml", "    mass_fraction: 0.9", "    mass_fraction: 90"); },
       expect_line("fabric.yaml", 9, "yarns[0].mass_fraction: a mass fraction is at most 1")},
      {"ZeroSwatchWidth", [](P d) { replace_in_file(d / "fabric.yaml", "width_mm: 60}", "width_mm: 0}"); },
       expect_line("fabric.yaml", 14, "swatch.width_mm: must be positive, got 0")},
      {"NegativeTestSwatchLength", [](P d) { replace_in_file(d / "fabric.yaml", "length_mm: 69.2", "length_mm: -69.2"); },
       expect_line("fabric.yaml", 19, "stretch_tests.warp.swatch.length_mm: must be positive")},
      {"NonPositiveGauge", [](P d) { replace_in_file(d / "fabric.yaml", "gauge: {length_mm: 59.4", "gauge: {length_mm: 0"); },
       expect_line("fabric.yaml", 20, "stretch_tests.warp.gauge.length_mm: must be positive")},
      {"GaugeLongerThanSwatch", [](P d) { replace_in_file(d / "fabric.yaml", "gauge: {length_mm: 59.4", "gauge: {length_mm: 75"); },
       expect_line("fabric.yaml", 20, "stretch_tests.warp.gauge.length_mm: gauge length 75 mm must be shorter")},
      {"GaugeWiderThanSwatch", [](P d) { replace_in_file(d / "fabric.yaml", "width_mm: 31.5}", "width_mm: 70}"); },
       expect_line("fabric.yaml", 20, "stretch_tests.warp.gauge.width_mm: gauge width 70 mm is wider")},
      {"NoSwatchAnywhere", [](P d) { replace_in_file(d / "fabric.yaml", "swatch: {length_mm: 100, width_mm: 60}\n", ""); },
       expect_line("fabric.yaml", 15, "stretch_tests.weft: no swatch size")},
      {"NumberAsText", [](P d) { replace_in_file(d / "fabric.yaml", "denier: 72", "denier: seventy"); },
       expect_line("fabric.yaml", 7, "yarns[0].denier: expected a number, got 'seventy'")},
      {"NaNInYaml", [](P d) { replace_in_file(d / "fabric.yaml", "areal_density_gsm: 200", "areal_density_gsm: .nan"); },
       expect_line("fabric.yaml", 4, "areal_density_gsm: NaN is not a valid value")},
      {"FractionalFilaments", [](P d) { replace_in_file(d / "fabric.yaml", "filaments: 75", "filaments: 7.5"); },
       expect_line("fabric.yaml", 8, "yarns[0].filaments: must be a whole number")},
      {"BendingWithoutArealDensity", [](P d) { replace_in_file(d / "fabric.yaml", "areal_density_gsm: 200\n", ""); },
       expect_line("fabric.yaml", 20, "areal_density_gsm: required when bending_tests are given")},
      {"NoStretchTests", [](P d) { replace_in_file(d / "fabric.yaml", "stretch_tests:\n  weft: {file: stretch_weft.csv}\n  warp:\n    file: stretch_warp.csv\n    swatch: {length_mm: 69.2, width_mm: 66.6}\n    gauge: {length_mm: 59.4, width_mm: 31.5}\n", ""); },
       expect_line("fabric.yaml", 1, "stretch_tests: missing required key")},
      {"EmptyYarnList", [](P d) { replace_in_file(d / "fabric.yaml", "yarns:\n", "yarns: []\nold_yarns:\n"); },
       expect_line("fabric.yaml", 5, "yarns: expected a non-empty list")},
      {"BadId", [](P d) { replace_in_file(d / "fabric.yaml", "id: T1", "id: T 1/2"); },
       expect_line("fabric.yaml", 1, "id: 'T 1/2' may use only")},
      // A record names files inside its own folder only (issue 47, SPEC §2).
      {"AbsoluteFile", [](P d) { replace_in_file(d / "fabric.yaml", "{file: stretch_weft.csv}", "{file: /etc/passwd}"); },
       expect_line("fabric.yaml", 16, "stretch_tests.weft.file: an absolute path")},
      {"FileLeavingTheFolder", [](P d) { replace_in_file(d / "fabric.yaml", "{file: bend_weft.csv}", "{file: ../T1/bend_weft.csv}"); },
       expect_line("fabric.yaml", 22, "bending_tests.weft.file: '../T1/bend_weft.csv' leaves the record's folder")},
      {"FileLinkedOut", [](P d) {
         write_file(d.parent_path() / "outside.csv", "stretch,force_N\n0,0\n0.1,1\n");
         fs::create_symlink(d.parent_path() / "outside.csv", d / "linked.csv");
         replace_in_file(d / "fabric.yaml", "{file: stretch_weft.csv}", "{file: linked.csv}");
       },
       expect_line("fabric.yaml", 16, "stretch_tests.weft.file: 'linked.csv' is a link that leaves the record's folder")},
      {"PatternFileAbsolute", [](P d) { add_pattern_line(d, "{file: /etc/hostname}"); },
       expect_line("fabric.yaml", 14, "pattern.file: an absolute path")},
      {"KnittingGaugeWithoutWales", [](P d) { replace_in_file(d / "fabric.yaml", "swatch: {length_mm: 100", "knitting_gauge: {courses_per_10cm: 52}\nswatch: {length_mm: 100"); },
       expect_line("fabric.yaml", 14, "knitting_gauge.wales_per_10cm: missing required key")},
      {"KnittingGaugeNegative", [](P d) { replace_in_file(d / "fabric.yaml", "swatch: {length_mm: 100", "knitting_gauge: {courses_per_10cm: -52, wales_per_10cm: 38}\nswatch: {length_mm: 100"); },
       expect_line("fabric.yaml", 14, "knitting_gauge.courses_per_10cm: must be positive")},
      {"ThicknessNotANumber", [](P d) { replace_in_file(d / "fabric.yaml", "swatch: {length_mm: 100", "thickness_mm: thick\nswatch: {length_mm: 100"); },
       expect_line("fabric.yaml", 14, "thickness_mm: expected a number")},
      {"FamilyNotUtf8", [](P d) { replace_in_file(d / "fabric.yaml", "family: test-family", "family: test-\xff\xfe"); },
       expect_line("fabric.yaml", 2, "family: not valid UTF-8 text")},
  };
}

// Names the case in test listings instead of dumping its bytes.
void PrintTo(const BrokenCase& c, std::ostream* os) { *os << c.name; }

class BrokenRecord : public ::testing::TestWithParam<BrokenCase> {};

TEST_P(BrokenRecord, ValidateNamesFileLineAndField) {
  const BrokenCase& c = GetParam();
  ScratchDir dir("broken");
  const fs::path fabric = dir / "T1";
  write_base_fabric(fabric);
  c.breaks(fabric);
  const auto r = run_cli("db validate " + quoted(fabric));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(fabric.string() + c.expected), std::string::npos)
      << "expected a line containing\n  " << fabric.string() + c.expected << "\nstderr was:\n" << r.err;
  // One problem per line, each in the `file:line: field: message` or `file: field: message` shape.
  std::istringstream lines(r.err);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("note:", 0) == 0) continue;
    EXPECT_EQ(line.rfind(dir.path().string(), 0), 0u) << "not a problem line: " << line;
    EXPECT_NE(line.find(": "), std::string::npos) << line;
  }
}

INSTANTIATE_TEST_SUITE_P(Rules, BrokenRecord, ::testing::ValuesIn(broken_cases()),
                         [](const auto& param_info) { return param_info.param.name; });

// A file the record may not read is refused by its name: nothing of it reaches a message, the
// local commands' (db validate, fit) as the service's (issue 47, defect 1).
TEST(ValidateRecord, NothingOfAFileOutsideTheRecordIsShown) {
  ScratchDir dir("outside");
  write_file(dir / "secret.csv", "SECRET-LINE-1,stretch\n0,0\n");
  for (const std::string& name : {(dir / "secret.csv").string(), std::string("../secret.csv"), std::string("/etc/passwd"),
                                  std::string("linked/secret.csv")}) {
    const fs::path fabric = dir / "T1";
    fs::remove_all(fabric);
    write_base_fabric(fabric);
    fs::create_directory_symlink(dir.path(), fabric / "linked");  // a linked folder on the way out
    replace_in_file(fabric / "fabric.yaml", "{file: stretch_weft.csv}", "{file: '" + name + "'}");
    for (const std::string& command : {"db validate " + quoted(fabric), "fit " + quoted(fabric) + " --out " + quoted(dir / "out")}) {
      const auto r = run_cli(command);
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
      EXPECT_TRUE(contains(r.err, "stretch_tests.weft.file: ")) << r.err;
      EXPECT_FALSE(contains(r.err, "SECRET-LINE") || contains(r.err, "root:")) << r.err;
      EXPECT_FALSE(fs::exists(dir / "out" / "shell_fit.json"));
    }
  }
}

TEST(ValidateRecord, BaseRecordIsValid) {
  ScratchDir dir("base");
  write_base_fabric(dir / "T1");
  const auto r = run_cli("db validate " + quoted(dir / "T1"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("1 fabric: 1 valid, 0 invalid"), std::string::npos) << r.out;
}

// A record may state its knitting gauge and thickness (SPEC §2); a knit pattern takes the gauge.
TEST(ValidateRecord, AKnittingGaugeAndThicknessAreRead) {
  ScratchDir dir("gauge");
  write_base_fabric(dir / "K");
  add_pattern_line(dir / "K", "{knit: stockinette, stitch_length_mm: 11.28, yarn_radius_mm: 0.74}");
  replace_in_file(dir / "K" / "fabric.yaml", "swatch: {length_mm: 100",
                  "knitting_gauge: {courses_per_10cm: 52, wales_per_10cm: 38}\nthickness_mm: 1.1\nswatch: {length_mm: 100");
  const auto load = yarnfit::db::load_fabric(dir / "K");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  ASSERT_TRUE(load.fabric->knitting_gauge);
  EXPECT_DOUBLE_EQ(load.fabric->knitting_gauge->courses_per_10cm, 52.0);
  EXPECT_DOUBLE_EQ(load.fabric->knitting_gauge->wale_spacing(), 0.1 / 38.0);
  EXPECT_DOUBLE_EQ(*load.fabric->thickness, 1.1e-3);
  ASSERT_TRUE(load.fabric->pattern->knit->gauge);
  EXPECT_EQ(*load.fabric->pattern->knit->gauge, *load.fabric->knitting_gauge);
}

// A pattern may name a knit whose tile yarnfit generates: read, with no tile yet.
TEST(ValidateRecord, AKnitPatternIsReadWithoutATile) {
  ScratchDir dir("knit_pattern");
  write_base_fabric(dir / "K");
  add_pattern_line(dir / "K", "{knit: rib2x2, stitch_length_mm: 16.1, yarn_radius_mm: 1.18}");
  const auto load = yarnfit::db::load_fabric(dir / "K");
  ASSERT_TRUE(load.ok()) << load.problems.to_string();
  const auto& pattern = load.fabric->pattern;
  ASSERT_TRUE(pattern && pattern->knit);
  EXPECT_EQ(pattern->knit->chart.text(), "kkpp");
  EXPECT_DOUBLE_EQ(pattern->knit->stitch_length, 16.1e-3);
  EXPECT_DOUBLE_EQ(pattern->knit->yarn_radius, 1.18e-3);
  EXPECT_FALSE(pattern->has_tile());
}

TEST(ValidateRecord, ReportsEveryProblemNotOnlyTheFirst) {
  ScratchDir dir("many");
  const fs::path f = dir / "T1";
  write_base_fabric(f);
  replace_in_file(f / "fabric.yaml", "family: test-family", "famly: test-family");
  replace_in_file(f / "fabric.yaml", "    mass_fraction: 0.1", "    mass_fraction: 0.5");
  replace_in_file(f / "stretch_weft.csv", "0.1,0.5,", "0.1,-0.5,");
  replace_in_file(f / "stretch_weft.csv", "0.3,2.4", "0.05,2.4");
  replace_in_file(f / "stretch_warp.csv", "0.2,1.2,0.05", "0.2,x,0.05");
  replace_in_file(f / "bend_weft.csv", "13,1.25", "13,-1");
  const auto r = run_cli("db validate " + quoted(f));
  EXPECT_EQ(r.exit_code, 2);
  for (const std::string expected :
       {"fabric.yaml:2: famly: unknown key", "fabric.yaml:1: family: missing required key",
        "fabric.yaml:5: yarns: mass fractions sum to 1.4", "stretch_weft.csv:3: force_N: negative force",
        "stretch_weft.csv:5: stretch: not strictly increasing", "stretch_warp.csv:4: force_N: expected a number",
        "bend_weft.csv:3: aspect_ratio: aspect ratio h/p must be positive"}) {
    EXPECT_NE(r.err.find(expected), std::string::npos) << expected << "\nstderr:\n" << r.err;
  }
  EXPECT_NE(r.out.find("7 problems"), std::string::npos) << r.out;
}

// Validation reads only: contents and modification times of the user's files stay as they were.
TEST(ValidateRecord, NeverModifiesTheFiles) {
  ScratchDir dir("readonly");
  const fs::path f = dir / "T1";
  write_base_fabric(f);
  replace_in_file(f / "stretch_weft.csv", "0.1,0.5,", "0.1,-0.5,");
  std::map<fs::path, std::pair<std::string, fs::file_time_type>> before;
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    if (e.is_regular_file()) before[e.path()] = {read_file(e.path()), fs::last_write_time(e.path())};
  EXPECT_EQ(run_cli("db validate " + quoted(f)).exit_code, 2);
  EXPECT_EQ(run_cli("db validate " + quoted(dir.path())).exit_code, 2);
  std::size_t after_count = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir.path())) {
    if (!e.is_regular_file()) continue;
    ++after_count;
    ASSERT_TRUE(before.count(e.path())) << "new file " << e.path();
    EXPECT_EQ(before[e.path()].first, read_file(e.path()));
    EXPECT_EQ(before[e.path()].second, fs::last_write_time(e.path()));
  }
  EXPECT_EQ(after_count, before.size());
}

}  // namespace
}  // namespace yarnfit::testing
