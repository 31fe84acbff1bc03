#pragma once
// The tile of a record whose pattern names a knit (`pattern: {knit: seed, stitch_length_mm:
// 15.67, yarn_radius_mm: 1.2}`, issue 20): generated and relaxed (yarn_fit/generate/
// knit_generation.hpp) when a yarn fit needs it, and kept in a cache folder beside the outputs,
// named by its inputs, so that the next fit of the same knit reads it instead. Never written
// into the fabric's folder.

#include <filesystem>
#include <string>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::yarn {

// "knit_<rows>_L<L mm>_R<R mm>[_C<courses>_W<wales> per 10 cm]" (rows with '/' as '-'): the cache name
// of a generated tile.
[[nodiscard]] std::string generated_tile_stem(const db::KnitSpec& knit);

// For a fabric whose pattern is a knit without a tile yet: reads `cache`/<stem>.pyp when it
// exists, else generates the tile (default yarn parameters with the record's ks2 and R_est =
// the yarn radius), writes <stem>.pyp and <stem>.json (its facts) into `cache`, and fills the
// pattern's file, tile and facts. Any other fabric is left alone (true). False, with the
// reason added to `problems` (field "pattern.knit"), when the tile cannot be made.
bool make_generated_pattern(db::Fabric& fabric, const std::filesystem::path& cache, db::Problems& problems);

}  // namespace yarnfit::yarn
