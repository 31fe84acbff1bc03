#pragma once
// `tile make` as one library call: a relaxed periodic yarn tile of a knit from its chart,
// stitch length and yarn radius (yarn_fit/generate/knit_generation.hpp), or a woven tile as
// constructed from its weave chart, yarn spacing and radius (fabrics_db/tile/woven_tile.hpp),
// checked, made and written as a pyp file.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"

namespace yarnfit::pipeline {

// In the units the user gives them. Exactly one of `chart` and `weave` is set.
struct TileRequest {
  std::string chart;        // knit chart: a name or rows of k and p ("kp/pk")
  std::string weave;        // weave chart: a name or rows of 1 and 0 ("10/01")
  std::string out;          // the .pyp to write
  std::string params_file;  // knits: yarn parameters (YAML/JSON); empty: SPEC §3's defaults
  double stitch_length_mm = 0.0;          // knits
  double yarn_spacing_mm = 0.0;           // woven tiles
  std::optional<double> weft_crimp_share; // woven tiles; unset: WovenTileOptions' default
  double yarn_radius_mm = 0.0;
  double ks2 = 400.0;         // knits: stiffness for the default parameters [N]
  std::vector<double> gauge;  // knits: courses, wales per 10 cm; empty: none
  double aspect = 0.0;        // knits: course / wale spacing without a gauge (0: Crane's)
  int vertices_per_stitch = 16;
  bool force = false;         // replace an existing `out`
};

struct MadeTile {
  bool written = false;   // the tile is in `out`
  std::string failure;    // why nothing was written (the knit's relaxation failed); else empty
  nlohmann::json facts;   // results::TileFile or results::WovenTileFile as JSON
  std::string summary;    // the same for a reader, one fact a line
};

// Every problem of the request (fields named as TileRequest's, or `out` as the file) before
// anything is made; nothing is made or written when there is one. A pyp that cannot be
// written throws an Error naming it; a knit that does not relax is a MadeTile
// with `failure`, and nothing written.
[[nodiscard]] MadeTile make_tile(const TileRequest& request, db::Problems& problems);

}  // namespace yarnfit::pipeline
