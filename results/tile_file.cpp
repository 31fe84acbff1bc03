#include "results/tile_file.hpp"

#include <limits>
#include <stdexcept>

#include "results/json_fields.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::results {

using nlohmann::json;
using namespace detail;

namespace {

using numerics::k_nan;

json pair_json(const std::array<double, 2>& v) { return numbers_json({v[0], v[1]}); }

std::array<double, 2> read_pair(const json& j, const char* key, const Where& at) {
  const std::vector<double> v = numbers(j, key, at);
  if (v.empty()) return {k_nan, k_nan};
  if (v.size() != 2) (at / key).bad("two numbers (weft, warp)");
  return {v[0], v[1]};
}

}  // namespace

json to_json(const TileFile& t) {
  json j = {{"schema_version", k_tile_schema_version},
            {"chart", t.chart},
            {"chart_rows", t.chart_rows},
            {"period_mm", pair_json(t.period_mm)},
            {"wale_spacing_mm", t.wale_spacing_mm},
            {"course_spacing_mm", t.course_spacing_mm},
            {"courses_per_cm", t.courses_per_cm},
            {"wales_per_cm", t.wales_per_cm},
            {"stitch_length_mm", t.stitch_length_mm},
            {"yarn_radius_mm", t.yarn_radius_mm},
            {"vertices", t.vertices},
            {"min_distance_mm", t.min_distance_mm},
            {"rest_stress_N_per_m", pair_json(t.rest_stress_N_per_m)},
            {"stress_at_10pct_N_per_m", pair_json(t.stress_at_10pct_N_per_m)},
            {"rest_stress_ratio", t.rest_stress_ratio},
            {"period_change", pair_json(t.period_change)},
            {"converged", t.converged},
            {"message", t.message},
            {"rounds", t.rounds},
            {"seconds", t.seconds},
            {"params", t.params}};
  if (t.file) j["file"] = string_or_null(*t.file);
  return j;
}

json to_json(const WovenTileFile& t) {
  return {{"schema_version", k_tile_schema_version},
          {"weave", t.weave},
          {"weave_rows", t.weave_rows},
          {"period_mm", pair_json(t.period_mm)},
          {"yarn_spacing_mm", t.yarn_spacing_mm},
          {"yarn_radius_mm", t.yarn_radius_mm},
          {"weft_crimp_share", t.weft_crimp_share},
          {"vertices", t.vertices},
          {"relaxed", false},
          {"file", t.file}};
}

TileFile tile_file_from_json(const json& j, const std::string& source) {
  const Where at(source);
  expect_object(j, at);
  TileFile t;
  t.schema_version = schema_version(j, at, k_tile_schema_version);
  t.chart = string(j, "chart", at);
  t.chart_rows = string(j, "chart_rows", at);
  t.period_mm = read_pair(j, "period_mm", at);
  t.wale_spacing_mm = number(j, "wale_spacing_mm", at, k_nan);
  t.course_spacing_mm = number(j, "course_spacing_mm", at, k_nan);
  t.courses_per_cm = number(j, "courses_per_cm", at, k_nan);
  t.wales_per_cm = number(j, "wales_per_cm", at, k_nan);
  t.stitch_length_mm = number(j, "stitch_length_mm", at, k_nan);
  t.yarn_radius_mm = number(j, "yarn_radius_mm", at, k_nan);
  t.vertices = long_integer(j, "vertices", at, 0);
  t.min_distance_mm = number(j, "min_distance_mm", at, k_nan);
  t.rest_stress_N_per_m = read_pair(j, "rest_stress_N_per_m", at);
  t.stress_at_10pct_N_per_m = read_pair(j, "stress_at_10pct_N_per_m", at);
  t.rest_stress_ratio = number(j, "rest_stress_ratio", at, k_nan);
  t.period_change = read_pair(j, "period_change", at);
  t.converged = boolean(j, "converged", at, false);
  t.message = string(j, "message", at);
  t.rounds = integer(j, "rounds", at, 0);
  t.seconds = number(j, "seconds", at, k_nan);
  t.params = number_map(j, "params", at);
  if (member(j, "file")) t.file = string(j, "file", at);
  return t;
}

TileFile read_tile_file(const std::filesystem::path& path) {
  return tile_file_from_json(read_json_file(path), path.string());
}

}  // namespace yarnfit::results
