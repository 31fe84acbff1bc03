// yarnfit db import-tensile: column mapping, units, header blocks, never overwriting.
#include "fabrics_db/import/tensile_import.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "tests/test_support.hpp"

namespace yarnfit::testing {
namespace {

// An export as a tensile tester writes it: metadata block, ';' separated, mm and cN.
const std::string k_export =
    "Instrument;ZwickLine Z0.5\n"           // 1
    "Operator;test\n"                       // 2
    "Specimen width [mm];60\n"              // 3
    "\n"                                    // 4
    "Time s;Extension mm;Force cN;Width mm\n"  // 5
    "0;0;0;60\n"                            // 6
    "1;10;55;58.8\n"                        // 7
    "2;20;130;57\n"                         // 8
    "3;30;260;54.6\n"                       // 9
    "4;25;120;55\n";                        // 10 (unloading)

db::TensileImportOptions mm_options(const fs::path& in, const fs::path& out) {
  db::TensileImportOptions o;
  o.input = in;
  o.output = out;
  o.extension = db::ColumnRef::parse("Extension mm");
  o.force = db::ColumnRef::parse("Force cN");
  o.width = db::ColumnRef::parse("Width mm");
  o.extension_unit = db::ExtensionUnit::mm;
  o.force_unit = db::ForceUnit::cN;
  o.gauge_length_mm = 100.0;
  o.swatch_width_mm = 60.0;
  return o;
}

TEST(TensileImport, ConvertsUnitsFindsHeaderAndKeepsLoadingBranch) {
  ScratchDir dir("import");
  write_file(dir / "export.txt", k_export);
  auto o = mm_options(dir / "export.txt", dir / "stretch_weft.csv");
  o.loading_branch = true;
  const auto r = db::import_tensile(o);
  ASSERT_TRUE(r.written) << r.problems.to_string();
  EXPECT_EQ(r.rows_read, 5u);
  EXPECT_EQ(r.rows_written, 4u);
  EXPECT_EQ(r.rows_dropped, 1u);
  EXPECT_EQ(r.curve.stretch, (std::vector<double>{0.0, 0.1, 0.2, 0.3}));
  EXPECT_DOUBLE_EQ(r.curve.force[3], 2.6);              // 260 cN
  EXPECT_NEAR(r.curve.compression[3], 1.0 - 54.6 / 60.0, 1e-12);  // 0.09

  // The written file reads back as a stretch test with the same values.
  db::Problems p;
  const auto table = db::read_csv(dir / "stretch_weft.csv", db::CsvOptions{}, p);
  ASSERT_TRUE(table) << p.to_string();
  const auto curve = db::read_stretch_curve(*table, p);
  ASSERT_TRUE(curve) << p.to_string();
  EXPECT_EQ(curve->stretch, r.curve.stretch);
  EXPECT_EQ(curve->force, r.curve.force);
}

TEST(TensileImport, ColumnsByIndexWithSkipLinesAndStretchUnit) {
  ScratchDir dir("import");
  write_file(dir / "raw.csv", "exported by rig 7\nt,s,F\n0,0,0\n1,0.05,0.8\n2,0.1,1.9\n");
  db::TensileImportOptions o;
  o.input = dir / "raw.csv";
  o.output = dir / "out.csv";
  o.extension = db::ColumnRef::parse("2");
  o.force = db::ColumnRef::parse("3");
  o.skip_lines = 1;
  const auto r = db::import_tensile(o);
  ASSERT_TRUE(r.written) << r.problems.to_string();
  EXPECT_EQ(r.curve.stretch, (std::vector<double>{0.0, 0.05, 0.1}));
  EXPECT_EQ(r.curve.force, (std::vector<double>{0.0, 0.8, 1.9}));
  EXPECT_FALSE(r.curve.has_compression());
  EXPECT_EQ(read_file(dir / "out.csv").find("stretch,force_N\n") != std::string::npos, true);
}

TEST(TensileImport, RefusesToOverwriteWithoutForce) {
  ScratchDir dir("import");
  write_file(dir / "export.txt", k_export);
  write_file(dir / "stretch_weft.csv", "precious\n");
  auto o = mm_options(dir / "export.txt", dir / "stretch_weft.csv");
  o.loading_branch = true;
  auto r = db::import_tensile(o);
  EXPECT_FALSE(r.written);
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_NE(r.problems.items()[0].message.find("--force"), std::string::npos);
  EXPECT_EQ(read_file(dir / "stretch_weft.csv"), "precious\n");
  o.overwrite = true;
  r = db::import_tensile(o);
  EXPECT_TRUE(r.written) << r.problems.to_string();
  EXPECT_NE(read_file(dir / "stretch_weft.csv"), "precious\n");
}

TEST(TensileImport, InvalidRowsAreReportedAgainstTheInputAndNothingIsWritten) {
  ScratchDir dir("import");
  write_file(dir / "export.txt", k_export);
  // Without --loading-branch the unloading row breaks the strictly increasing stretch.
  auto r = db::import_tensile(mm_options(dir / "export.txt", dir / "out.csv"));
  EXPECT_FALSE(r.written);
  EXPECT_FALSE(fs::exists(dir / "out.csv"));
  ASSERT_EQ(r.problems.size(), 1u) << r.problems.to_string();
  EXPECT_EQ(r.problems.items()[0].line, 10);
  EXPECT_EQ(r.problems.items()[0].field, "stretch");

  std::string bad = k_export;
  bad.replace(bad.find("2;20;130;57"), 11, "2;20;abc;57");
  write_file(dir / "bad.txt", bad);
  auto o = mm_options(dir / "bad.txt", dir / "out.csv");
  o.loading_branch = true;
  r = db::import_tensile(o);
  EXPECT_FALSE(r.written);
  ASSERT_EQ(r.problems.size(), 1u) << r.problems.to_string();
  EXPECT_EQ(r.problems.items()[0].to_string(),
            (dir / "bad.txt").string() + ":8: Force cN: expected a number, got 'abc'");
}

TEST(TensileImport, MissingOptionsAndColumnsAreExplained) {
  ScratchDir dir("import");
  write_file(dir / "export.txt", k_export);
  auto o = mm_options(dir / "export.txt", dir / "out.csv");
  o.gauge_length_mm.reset();
  o.swatch_width_mm.reset();
  auto r = db::import_tensile(o);
  EXPECT_EQ(r.problems.size(), 2u) << r.problems.to_string();
  o = mm_options(dir / "export.txt", dir / "out.csv");
  o.force = db::ColumnRef::parse("Load N");
  r = db::import_tensile(o);
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_NE(r.problems.items()[0].message.find("no line holds all of"), std::string::npos);
  o = mm_options(dir / "export.txt", dir / "out.csv");
  o.force = db::ColumnRef::parse("9");
  o.loading_branch = true;
  r = db::import_tensile(o);
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_EQ(r.problems.items()[0].field, "--force-col");
  EXPECT_EQ(r.problems.items()[0].line, 5);
}

TEST(TensileImport, CommandLine) {
  ScratchDir dir("import");
  write_file(dir / "export.txt", k_export);
  const std::string args = "db import-tensile " + quoted(dir / "export.txt") + " --out " +
                           quoted(dir / "s.csv") +
                           " --stretch-col 'Extension mm' --force-col 'Force cN' --width-col 'Width mm'"
                           " --extension-unit mm --gauge-length-mm 100 --force-unit cN"
                           " --swatch-width-mm 60 --loading-branch";
  auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 rows (1 dropped"), std::string::npos) << r.out;
  r = run_cli(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("file exists; pass --force"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli(args + " --force").exit_code, 0);
  r = run_cli(args + " --force-unit lbf");
  EXPECT_EQ(r.exit_code, 2);
}

// A real measured curve goes through the importer unchanged (columns by name).
TEST(TensileImport, RealMergedCurve) {
  const fs::path src = shared_dir() / "data/measured/stitch-by-stitch/acrylic/rib_x_merged.csv";
  YARNFIT_REQUIRE_SHARED(src);
  ScratchDir dir("import");
  db::TensileImportOptions o;
  o.input = src;
  o.output = dir / "rib_weft.csv";
  o.extension = db::ColumnRef::parse("stretch");
  o.force = db::ColumnRef::parse("force_N");
  o.compression = db::ColumnRef::parse("compression");
  const auto r = db::import_tensile(o);
  ASSERT_TRUE(r.written) << r.problems.to_string();
  EXPECT_EQ(r.rows_written, 25u);
  EXPECT_GT(r.curve.stretch.back(), 1.0);  // the rib stretches past 100 % along X
  EXPECT_TRUE(fs::exists(src));           // the source is untouched
}

}  // namespace
}  // namespace yarnfit::testing
