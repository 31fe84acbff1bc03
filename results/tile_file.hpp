#pragma once
// A generated knit tile's record as a type: what `tile make --json` prints and what the fit
// keeps beside a generated tile's .pyp (DIR/<chart>_L…_R….json): the chart, the relaxed
// period and spacings, how far the relaxation got and the yarn parameters it ran with. The tile
// generator fills it (yarn::to_file, yarn_fit/generate/knit_generation.hpp); to_json writes it
// and tile_file_from_json reads it, of this version or an older one.
//
// Schema versions:
//   1  no `schema_version` key (every record before the results module);
//   2  `schema_version` 2; otherwise the same fields.

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace yarnfit::results {

inline constexpr int k_tile_schema_version = 2;

struct TileFile {
  int schema_version = k_tile_schema_version;  // as read; to_json writes the current one
  std::string chart;                           // the chart's name
  std::string chart_rows;                      // its rows as text
  std::array<double, 2> period_mm{};           // relaxed period, x (weft) and y (warp)
  double wale_spacing_mm = 0.0;
  double course_spacing_mm = 0.0;
  double courses_per_cm = 0.0;
  double wales_per_cm = 0.0;
  double stitch_length_mm = 0.0;  // yarn length per stitch at rest
  double yarn_radius_mm = 0.0;
  long long vertices = 0;
  double min_distance_mm = 0.0;  // closest approach of two yarns
  std::array<double, 2> rest_stress_N_per_m{};      // weft, warp
  std::array<double, 2> stress_at_10pct_N_per_m{};  // weft, warp
  double rest_stress_ratio = 0.0;
  std::array<double, 2> period_change{};  // relaxed over initial period, minus 1
  bool converged = false;
  std::string message;
  int rounds = 0;
  double seconds = 0.0;
  std::map<std::string, double> params;  // the yarn parameters of the relaxation, SI
  // The .pyp written (tile make): empty when none was, absent from the fit's records.
  std::optional<std::string> file;
};

// A woven tile as `tile make --json` prints it: built from its weave, not relaxed.
struct WovenTileFile {
  std::string weave;       // the weave's name
  std::string weave_rows;  // its rows as text
  std::array<double, 2> period_mm{};
  double yarn_spacing_mm = 0.0;
  double yarn_radius_mm = 0.0;
  long long vertices = 0;
  std::string file;  // the .pyp written
  double weft_crimp_share = 0.0;  // the weft's share of the crimp at a crossing
};

[[nodiscard]] nlohmann::json to_json(const TileFile& file);
[[nodiscard]] nlohmann::json to_json(const WovenTileFile& file);
// A tile record of any version; a field of the wrong type throws an Error naming it.
[[nodiscard]] TileFile tile_file_from_json(const nlohmann::json& json, const std::string& source = "tile.json");
[[nodiscard]] TileFile read_tile_file(const std::filesystem::path& path);

}  // namespace yarnfit::results
