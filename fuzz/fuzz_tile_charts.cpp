// The knit and weave charts of `yarnfit tile make --chart/--weave`: text a user types. Both
// parsers answer nullopt with a reason. A parsed chart of a few stitches is made into a tile,
// which may refuse it only with the documented Error of category input.
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/knit_tile.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "fuzz/fuzz_support.hpp"
#include "numerics/util/error.hpp"

namespace {

// A generator on a parsed chart: refused with an input Error, or a tile.
template <class Make>
void make_or_refuse(Make make) {
  try {
    (void)make();
  } catch (const yarnfit::Error& e) {
    if (e.category() != yarnfit::ErrorCategory::input) yarnfit::fuzz::finding(e.what());
  }
}

}  // namespace

YARNFIT_FUZZ_TARGET(tile_charts) {
  using namespace yarnfit;
  if (size > 4096) return 0;  // charts are a few rows
  const std::string text(fuzz::as_text(data, size));
  const bool small = size <= 40;  // tiles grow with the chart; a few repeats cover the generators
  std::string why;
  if (const auto knit = db::parse_knit_chart(text, &why); knit && small) {
    db::KnitTileOptions options;
    options.stitch_length = 5e-3;
    options.yarn_radius = 0.25e-3;
    options.vertices_per_stitch = 8;
    make_or_refuse([&] { return db::make_knit_tile(*knit, options); });
  }
  if (const auto weave = db::parse_weave_chart(text, &why); weave && small) {
    db::WovenTileOptions options;
    options.yarn_spacing = 1.5e-3;
    options.yarn_radius = 0.25e-3;
    options.vertices_per_crossing = 2;
    make_or_refuse([&] { return db::make_woven_tile(*weave, options); });
  }
  return 0;
}
