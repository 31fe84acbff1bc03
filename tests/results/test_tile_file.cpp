// A generated tile's record as results::TileFile (results/tile_file.hpp): a record of schema
// version 1 (kept by a batch of the version before the type) reads and writes back the same
// fields and numbers, and a bad field is named.
#include <gtest/gtest.h>

#include <string>

#include "tests/expect_error.hpp"
#include "tests/test_support.hpp"

#include "results/tile_file.hpp"

namespace yarnfit::results {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace yarnfit::testing;

// The stockinette tile an acrylic batch generated (knit k, L 11.28 mm, R 0.74 mm).
json tile_version_1() { return json::parse(read_file(fs::path(YARNFIT_SOURCE_DIR) / "tests/results/data/tile_v1.json")); }

TEST(TileFile, AVersion1RecordReadsAndWritesBackTheSameFieldsAndNumbers) {
  const json v1 = tile_version_1();
  ASSERT_FALSE(v1.contains("schema_version"));
  const TileFile t = tile_file_from_json(v1);
  EXPECT_EQ(t.schema_version, 1);
  EXPECT_EQ(t.chart, v1["chart"].get<std::string>());
  EXPECT_EQ(t.period_mm[1], v1["period_mm"][1].get<double>());
  EXPECT_EQ(t.params.at("R1"), v1["params"]["R1"].get<double>());
  EXPECT_FALSE(t.file.has_value());
  json again = to_json(t);
  EXPECT_EQ(again["schema_version"], k_tile_schema_version);
  again.erase("schema_version");
  EXPECT_EQ(again, v1) << json::diff(v1, again).dump(1);
}

TEST(TileFile, TheFileTileMakeWroteIsNullWhenItWroteNone) {
  TileFile t = tile_file_from_json(tile_version_1());
  t.file = "";
  EXPECT_TRUE(to_json(t)["file"].is_null());
  t.file = "out/k.pyp";
  EXPECT_EQ(tile_file_from_json(to_json(t)).file, "out/k.pyp");
}

TEST(TileFile, ABadFieldIsNamed) {
  json v1 = tile_version_1();
  v1["period_mm"] = json::array({1.0, 2.0, 3.0});
  try {
    (void)tile_file_from_json(v1, "t.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "t.json: period_mm: expected two numbers (weft, warp)");
    EXPECT_EQ(e.category(), ErrorCategory::input);
  }
}

// What the user can do differs: a file that is not there (io) or one that is not a tile record
// (input).
TEST(TileFile, AMissingFileIsAnIoErrorAndAWrongOneAnInputError) {
  const testing::ScratchDir dir("tile_file_errors");
  EXPECT_ERROR((void)read_tile_file(dir / "none.json"), ErrorCategory::io);
  testing::write_file(dir / "list.json", "[1, 2]\n");
  EXPECT_ERROR((void)read_tile_file(dir / "list.json"), ErrorCategory::input);
  testing::write_file(dir / "text.json", "not JSON\n");
  EXPECT_ERROR((void)read_tile_file(dir / "text.json"), ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::results
