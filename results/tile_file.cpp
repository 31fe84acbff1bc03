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

constexpr std::array<double, 2> k_no_pair{k_nan, k_nan};

// A relaxed knit tile's fields, each with the value a file without it reads as; `schema_version`
// and `file` are the writer's and the reader's own.
template <class Fields, class Tile>
void tile_fields(Fields& f, Tile& t) {
  f("chart", t.chart, std::string());
  f("chart_rows", t.chart_rows, std::string());
  f("period_mm", t.period_mm, k_no_pair);
  f("wale_spacing_mm", t.wale_spacing_mm, k_nan);
  f("course_spacing_mm", t.course_spacing_mm, k_nan);
  f("courses_per_cm", t.courses_per_cm, k_nan);
  f("wales_per_cm", t.wales_per_cm, k_nan);
  f("stitch_length_mm", t.stitch_length_mm, k_nan);
  f("yarn_radius_mm", t.yarn_radius_mm, k_nan);
  f("vertices", t.vertices, 0LL);
  f("min_distance_mm", t.min_distance_mm, k_nan);
  f("rest_stress_N_per_m", t.rest_stress_N_per_m, k_no_pair);
  f("stress_at_10pct_N_per_m", t.stress_at_10pct_N_per_m, k_no_pair);
  f("rest_stress_ratio", t.rest_stress_ratio, k_nan);
  f("period_change", t.period_change, k_no_pair);
  f("converged", t.converged, false);
  f("message", t.message, std::string());
  f("rounds", t.rounds, 0);
  f("seconds", t.seconds, k_nan);
  f("params", t.params, std::map<std::string, double>());
}

}  // namespace

json to_json(const TileFile& t) {
  json j = {{"schema_version", k_tile_schema_version}};
  FieldWriter w(j);
  tile_fields(w, t);
  if (t.file) j["file"] = string_or_null(*t.file);
  return j;
}

json to_json(const WovenTileFile& t) {
  return {{"schema_version", k_tile_schema_version},
          {"weave", t.weave},
          {"weave_rows", t.weave_rows},
          {"period_mm", numbers_json({t.period_mm[0], t.period_mm[1]})},
          {"yarn_spacing_mm", t.yarn_spacing_mm},
          {"yarn_radius_mm", t.yarn_radius_mm},
          {"weft_crimp_share", t.weft_crimp_share},
          {"vertices", t.vertices},
          {"relaxed", false},
          {"file", t.file}};
}

TileFile tile_file_from_json(const json& j, const std::string& source) {
  const Where at(source);
  TileFile t = open_result<TileFile>(j, at, k_tile_schema_version);
  const FieldReader f(j, at);
  tile_fields(f, t);
  if (member(j, "file")) t.file = string(j, "file", at);
  return t;
}

TileFile read_tile_file(const std::filesystem::path& path) {
  return tile_file_from_json(read_json_file(path), path.string());
}

}  // namespace yarnfit::results
