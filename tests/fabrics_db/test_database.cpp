// A database of several fabrics: one run reports every problem of every fabric and still
// validates the good ones (issue 2, acceptance 3).
#include <map>

#include "fabrics_db/records/database.hpp"
#include "tests/fabrics_db/fabric_fixture.hpp"

namespace yarnfit::testing {
namespace {

// good_a, good_b valid; bad_yaml, bad_csv broken; dup_1/dup_2 share an id.
void write_mixed_database(const fs::path& db) {
  write_base_fabric(db / "good_a", "A1");
  write_base_fabric(db / "good_b", "B1");
  replace_in_file(db / "good_b" / "fabric.yaml", "family: test-family", "family: other-family");
  write_base_fabric(db / "bad_yaml", "C1");
  replace_in_file(db / "bad_yaml" / "fabric.yaml", "  weft: {file: stretch_weft.csv}", "  left: {file: stretch_weft.csv}");
  replace_in_file(db / "bad_yaml" / "fabric.yaml", "width_mm: 60}", "width_mm: -1}");
  write_base_fabric(db / "bad_csv", "D1");
  replace_in_file(db / "bad_csv" / "stretch_warp.csv", "0.1,0.5,0.02", "0.1,nan,0.02");
  replace_in_file(db / "bad_csv" / "bend_weft.csv", "34,1.08", "20,1.08");
  write_base_fabric(db / "dup_1", "E1");
  write_base_fabric(db / "dup_2", "E1");
  fs::create_directories(db / "notes");  // not a fabric: skipped with a note
  write_file(db / "README.txt", "not a fabric\n");
}

TEST(Database, LoadsAllFabricsAndKeepsGoingPastBrokenOnes) {
  ScratchDir dir("db");
  write_mixed_database(dir.path());
  const auto db = db::load_database(dir.path());
  ASSERT_EQ(db.fabrics.size(), 6u);
  EXPECT_EQ(db.valid_count(), 2u);
  std::map<std::string, const db::FabricLoad*> by_folder;
  for (const auto& f : db.fabrics) by_folder[f.folder.filename().string()] = &f;
  EXPECT_TRUE(by_folder["good_a"]->ok());
  EXPECT_TRUE(by_folder["good_b"]->ok());
  EXPECT_EQ(by_folder["good_b"]->fabric->family, "other-family");
  EXPECT_EQ(by_folder["bad_yaml"]->problems.size(), 2u) << by_folder["bad_yaml"]->problems.to_string();
  EXPECT_EQ(by_folder["bad_csv"]->problems.size(), 2u) << by_folder["bad_csv"]->problems.to_string();
  EXPECT_EQ(by_folder["bad_yaml"]->id, "C1");  // best-effort id even when invalid
  EXPECT_FALSE(by_folder["dup_1"]->ok());
  EXPECT_FALSE(by_folder["dup_2"]->ok());
  ASSERT_EQ(db.notes.size(), 1u);
  EXPECT_NE(db.notes[0].find("notes"), std::string::npos);
}

TEST(Database, ValidateReportsEveryProblemOfEveryFabricInOneRun) {
  ScratchDir dir("db");
  write_mixed_database(dir.path());
  const auto r = run_cli("db validate " + quoted(dir.path()));
  EXPECT_EQ(r.exit_code, 2);
  const std::string root = dir.path().string();
  for (const std::string& expected : {
           root + "/bad_yaml/fabric.yaml:16: stretch_tests.left: unknown direction",
           root + "/bad_yaml/fabric.yaml:14: swatch.width_mm: must be positive",
           root + "/bad_csv/stretch_warp.csv:3: force_N: NaN is not a valid value",
           root + "/bad_csv/bend_weft.csv:5: clamp_distance_mm: not strictly increasing",
           root + "/dup_1/fabric.yaml:1: id: duplicate id 'E1' in the database (also used by " + root + "/dup_2/fabric.yaml)",
           root + "/dup_2/fabric.yaml:1: id: duplicate id 'E1' in the database (also used by " + root + "/dup_1/fabric.yaml)",
       }) {
    EXPECT_NE(r.err.find(expected), std::string::npos) << expected << "\nstderr:\n" << r.err;
  }
  EXPECT_NE(r.out.find("ok       A1  " + root + "/good_a"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ok       B1  " + root + "/good_b"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("invalid  C1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("6 fabrics: 2 valid, 4 invalid; 6 problems"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("note: skipped " + root + "/notes"), std::string::npos) << r.err;
}

TEST(Database, ListShowsValidAndInvalidFabricsAndFiltersByFamily) {
  ScratchDir dir("db");
  write_mixed_database(dir.path());
  auto r = run_cli("db list " + quoted(dir.path()) + " --json");
  EXPECT_EQ(r.exit_code, 2);  // the database holds invalid fabrics
  const auto all = nlohmann::json::parse(r.out);
  ASSERT_EQ(all.size(), 6u);
  EXPECT_EQ(all[0]["folder"], (dir.path() / "bad_csv").string());
  EXPECT_EQ(all[0]["valid"], false);

  r = run_cli("db list " + quoted(dir.path()) + " --family other-family --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;  // the listed fabrics are all valid
  const auto other = nlohmann::json::parse(r.out);
  ASSERT_EQ(other.size(), 1u);
  EXPECT_EQ(other[0]["id"], "B1");
  EXPECT_EQ(other[0]["stretch_tests"], nlohmann::json::array({"weft", "warp"}));
  EXPECT_EQ(other[0]["bending_tests"], nlohmann::json::array({"weft"}));
  EXPECT_EQ(other[0]["pattern"], false);

  r = run_cli("db list " + quoted(dir.path()) + " --family other-family");
  EXPECT_NE(r.out.find("B1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 fabric\n"), std::string::npos) << r.out;
}

TEST(Database, EmptyOrMissingFolderIsInvalidInput) {
  ScratchDir dir("empty");
  auto r = run_cli("db validate " + quoted(dir.path()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(dir.path().string() + ": file: no fabric found"), std::string::npos) << r.err;
  r = run_cli("db validate " + quoted(dir / "missing"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing: file: no such folder"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace yarnfit::testing
