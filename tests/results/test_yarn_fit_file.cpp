// yarn_fit.json as results::YarnFitFile (results/yarn_fit_file.hpp): a file of schema version 1
// (a real batch output of the version before the type) reads and writes back to the same JSON
// with only the version added, both local steps' records round-trip, the readers' figures come
// from the type, and a bad field is named.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "tests/test_support.hpp"

#include "results/yarn_fit_file.hpp"

namespace yarnfit::results {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace yarnfit::testing;

// `yarnfit batch --budget quick` on the bundled stockinette_light, written by the commit before
// the results module (bd6c6bd): no schema_version, the staged search and the Gauss–Newton step.
json yarn_fit_version_1() {
  return json::parse(read_file(fs::path(YARNFIT_SOURCE_DIR) / "tests/results/data/yarn_fit_v1.json"));
}

TEST(YarnFitFile, AVersion1FileReadsAndWritesBackTheSameFieldsAndNumbers) {
  const json v1 = yarn_fit_version_1();
  ASSERT_FALSE(v1.contains("schema_version"));
  const YarnFitFile file = yarn_fit_file_from_json(v1);
  EXPECT_EQ(file.schema_version, 1);
  json again = to_json(file);
  EXPECT_EQ(again["schema_version"], k_yarn_fit_schema_version);
  again.erase("schema_version");
  // Every field, nested ones included, and every number to the last bit (JSON keeps doubles).
  EXPECT_EQ(again, v1) << json::diff(v1, again).dump(1);
}

TEST(YarnFitFile, TheFiguresReadersShowComeFromTheType) {
  const json v1 = yarn_fit_version_1();
  const YarnFitFile f = yarn_fit_file_from_json(v1);
  EXPECT_EQ(f.fabric, v1["fabric"].get<std::string>());
  EXPECT_TRUE(f.ok);
  EXPECT_EQ(f.errors.stress_comfort_pct, v1["errors"]["stress_comfort_pct"].get<double>());
  ASSERT_EQ(f.curves.size(), v1["curves"].size());
  EXPECT_EQ(f.curves[0].direction, v1["curves"][0]["direction"].get<std::string>());
  EXPECT_EQ(f.curves[0].simulated_S_N_per_m.size(), v1["curves"][0]["simulated_S_N_per_m"].size());
  for (const auto& [dir, e] : v1["errors_by_direction"].items())
    EXPECT_EQ(f.errors_by_direction.at(dir).comfort_stretch, e["comfort_stretch"].get<double>()) << dir;
  EXPECT_EQ(f.timing_s.total, v1["timing_s"]["total"].get<double>());
  EXPECT_EQ(f.params.at("R1"), v1["params"]["R1"].get<double>());
  ASSERT_TRUE(f.local.has_value());
  EXPECT_EQ(f.local->best.method, "gauss-newton");
  ASSERT_TRUE(f.local->best.rounds.has_value());
  EXPECT_EQ(f.local->best.rounds->size(), v1["local"]["rounds"].size());
  EXPECT_EQ(named_errors(f.errors).at("compression_pct"), f.errors.compression_pct);
}

// The other local step (implicit filtering) and a failed fit: their optional parts round-trip.
TEST(YarnFitFile, ImplicitFilteringAndAFailedFitRoundTrip) {
  YarnFitFile f;
  f.ok = false;
  f.message = "every candidate failed";
  f.errors_reason = f.message;
  f.errors = {std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  f.objective = std::nan("");
  f.params = {{"ks1", 1.0}, {"R1", 2e-4}};
  f.bending_check = CheckOutcome{false, "no bending targets"};
  f.settings.local_method = "implicit-filtering";
  f.settings.start = std::map<std::string, double>{{"ks1", 1.0}};
  f.settings.resumed_from = "fit.ckpt";
  LocalRunRecord run;
  run.method = "implicit-filtering";
  run.best = std::nan("");
  run.iterations = 3;
  run.final_scale = 0.0125;
  run.history = std::vector<FilteringIterationRecord>{{10, 0.1, 2.5, "shrink", 4}};
  f.local = LocalRecord{run, {run, run}};
  const json j = to_json(f);
  EXPECT_TRUE(j["errors"]["stress_comfort_pct"].is_null());  // no figure: null, not 0
  EXPECT_TRUE(j["objective"].is_null());
  EXPECT_FALSE(j["local"].contains("rounds"));
  const YarnFitFile back = yarn_fit_file_from_json(j);
  EXPECT_EQ(to_json(back), j);
  EXPECT_TRUE(std::isnan(back.errors.stress_full_pct));
  ASSERT_TRUE(back.local && back.local->best.history);
  EXPECT_EQ(back.local->best.history->at(0).move, "shrink");
  EXPECT_EQ(back.local->runs.size(), 2u);
  EXPECT_EQ(back.settings.resumed_from, "fit.ckpt");
}

TEST(YarnFitFile, ABadFieldIsNamedWithItsPath) {
  json v1 = yarn_fit_version_1();
  v1["curves"][1]["stretch"] = "0.1";
  try {
    (void)yarn_fit_file_from_json(v1, "out/yarn_fit.json");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "out/yarn_fit.json: curves[1].stretch: expected an array of numbers (found string)");
  }
  json newer = yarn_fit_version_1();
  newer["schema_version"] = k_yarn_fit_schema_version + 1;
  EXPECT_THROW((void)yarn_fit_file_from_json(newer), std::runtime_error);
  json no_params = yarn_fit_version_1();
  no_params.erase("params");
  EXPECT_THROW((void)yarn_fit_file_from_json(no_params), std::runtime_error);
  const ScratchDir dir("results_yarn");
  yarnfit::testing::write_file(dir / "yarn_fit.json", "{not json");
  EXPECT_THROW((void)read_yarn_fit_file(dir / "yarn_fit.json"), std::runtime_error);
}


// yarn_fit.json's `tile` (issue 48): written and read back field for field, a tile without a
// count or a record gauge as null or absent, and a bad field named with its path.
TEST(YarnFitFile, TheFittedTileRoundTripsAndABadFieldIsNamed) {
  YarnFitFile f = yarn_fit_file_from_json(yarn_fit_version_1());
  FittedTileRecord t;
  t.source = "generated at the record's gauge";
  t.period_weft_mm = 2.4, t.period_warp_mm = 1.25, t.yarn_radius_mm = 0.25;
  t.wales = 2, t.courses = 3;
  t.wales_per_10cm = 83.3, t.courses_per_10cm = 240.0;
  t.record_wales_per_10cm = 80.0, t.record_courses_per_10cm = 230.0;
  f.tile = t;
  const json j = to_json(f);
  EXPECT_EQ(j.at("tile").at("record_gauge").at("courses_per_10cm"), 230.0);
  const YarnFitFile back = yarn_fit_file_from_json(j);
  ASSERT_TRUE(back.tile);
  EXPECT_EQ(back.tile->source, t.source);
  EXPECT_EQ(back.tile->wales, 2);
  EXPECT_EQ(back.tile->courses, 3);
  EXPECT_EQ(back.tile->period_warp_mm, 1.25);
  EXPECT_EQ(back.tile->wales_per_10cm, 83.3);
  EXPECT_EQ(back.tile->record_wales_per_10cm, 80.0);
  EXPECT_EQ(to_json(back), j);
  // Not a weft knit, no gauge in the record.
  f.tile->wales = f.tile->courses = 0;
  f.tile->wales_per_10cm = f.tile->courses_per_10cm = std::nan("");
  f.tile->record_wales_per_10cm.reset();
  f.tile->record_courses_per_10cm.reset();
  const json k = to_json(f);
  EXPECT_TRUE(k.at("tile").at("wales_per_10cm").is_null());
  EXPECT_FALSE(k.at("tile").contains("record_gauge"));
  const YarnFitFile none = yarn_fit_file_from_json(k);
  EXPECT_TRUE(std::isnan(none.tile->courses_per_10cm));
  EXPECT_FALSE(none.tile->record_courses_per_10cm);
  // Files from before issue 48 have no tile.
  EXPECT_FALSE(yarn_fit_file_from_json(yarn_fit_version_1()).tile);
  json bad = j;
  bad["tile"]["period_mm"]["warp"] = "1.25";
  try {
    (void)yarn_fit_file_from_json(bad, "out/yarn_fit.json");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("out/yarn_fit.json: tile.period_mm.warp"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace yarnfit::results
