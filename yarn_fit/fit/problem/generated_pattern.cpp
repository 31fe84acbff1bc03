#include "yarn_fit/fit/problem/generated_pattern.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "yarn_fit/generate/knit_generation.hpp"

namespace yarnfit::yarn {

namespace fs = std::filesystem;

std::string generated_tile_stem(const db::KnitSpec& knit) {
  std::string rows = knit.chart.text();
  for (char& c : rows)
    if (c == '/') c = '-';
  char buf[96];
  std::snprintf(buf, sizeof buf, "_L%.6gmm_R%.6gmm", 1e3 * knit.stitch_length, 1e3 * knit.yarn_radius);
  std::string stem = "knit_" + rows + buf;
  if (knit.gauge) {
    std::snprintf(buf, sizeof buf, "_C%.6g_W%.6g", knit.gauge->courses_per_10cm, knit.gauge->wales_per_10cm);
    stem += buf;
  }
  return stem;
}

bool make_generated_pattern(db::Fabric& fabric, const fs::path& cache, db::Problems& problems) {
  if (!fabric.pattern || !fabric.pattern->knit || fabric.pattern->has_tile()) return true;
  db::PatternRef& pattern = *fabric.pattern;
  const db::KnitSpec& knit = *pattern.knit;
  const std::string yaml = (fabric.folder / db::k_fabric_file_name).string();
  const fs::path file = cache / (generated_tile_stem(knit) + ".pyp");
  std::error_code ec;
  if (fs::is_regular_file(file, ec)) {
    db::Problems found;
    if (auto tile = db::read_pyp(file, found)) {
      pattern.file = file;
      pattern.tile = std::move(*tile);
      pattern.facts = db::compute_tile_facts(pattern.tile);
      return true;
    }
    // A damaged cache entry is made again below.
  }
  yarn::TileGenerationOptions options;
  options.geometry.stitch_length = knit.stitch_length;
  options.geometry.yarn_radius = knit.yarn_radius;
  if (knit.gauge) {
    options.geometry.wale_spacing = knit.gauge->wale_spacing();
    options.geometry.course_spacing = knit.gauge->course_spacing();
  }
  if (const auto ks2 = fabric.stiffest_yarn_stiffness()) options.default_ks2 = *ks2;
  yarn::GeneratedTile generated;
  try {
    generated = yarn::generate_knit_tile(knit.chart, options);
  } catch (const Error& e) {
    if (e.category() != ErrorCategory::input) throw;  // only a refused chart or geometry is the user's
    problems.add(yaml, 0, "pattern.knit", e.what());
    return false;
  }
  if (!generated.converged) {
    problems.add(yaml, 0, "pattern.knit", "the generated " + knit.chart.name + " tile did not relax: " + generated.message);
    return false;
  }
  fs::create_directories(cache, ec);
  db::write_pyp(generated.tile, file);
  db::write_text_file_atomically(cache / (generated_tile_stem(knit) + ".json"), results::to_json(yarn::to_file(generated)).dump(2) + "\n");
  pattern.file = file;
  pattern.tile = std::move(generated.tile);
  pattern.facts = db::compute_tile_facts(pattern.tile);
  return true;
}

}  // namespace yarnfit::yarn
