#include "pipeline/fitted_tile.hpp"

#include <limits>
#include <optional>

#include "fabrics_db/tile/knit_gauge.hpp"

namespace yarnfit::pipeline {

results::FittedTileRecord describe_fitted_tile(const db::Fabric& fabric, const db::PeriodicTile& tile, bool shape_fitted,
                                               bool shape_held) {
  results::FittedTileRecord r;
  const db::Axis weft = fabric.pattern ? fabric.pattern->weft_axis : db::Axis::x;
  const std::optional<db::KnitSpec>& knit = fabric.pattern ? fabric.pattern->knit : std::nullopt;
  if (shape_fitted) r.source = shape_held ? "shape search (period held at the fitted aspect)" : "generated from the chart (the shape search kept it)";
  else if (knit && knit->gauge) r.source = "generated at the record's gauge";
  else if (knit) r.source = "generated from the chart";
  else r.source = "the record's tile file";
  r.period_weft_mm = 1e3 * (weft == db::Axis::x ? tile.period_x : tile.period_y);
  r.period_warp_mm = 1e3 * (weft == db::Axis::x ? tile.period_y : tile.period_x);
  r.yarn_radius_mm = 1e3 * tile.radius;
  std::optional<db::TileGauge> g;
  if (knit) g = db::gauge_of_counts(tile, weft, knit->chart.wales(), knit->chart.courses());
  else g = db::count_knit_gauge(tile, db::compute_tile_facts(tile), weft);
  r.wales_per_10cm = r.courses_per_10cm = std::numeric_limits<double>::quiet_NaN();
  if (g) {
    r.wales = g->wales;
    r.courses = g->courses;
    r.wales_per_10cm = g->wales_per_10cm();
    r.courses_per_10cm = g->courses_per_10cm();
  }
  std::optional<db::KnittingGauge> stated = fabric.knitting_gauge;
  if (!stated && knit) stated = knit->gauge;
  if (stated) {
    r.record_wales_per_10cm = stated->wales_per_10cm;
    r.record_courses_per_10cm = stated->courses_per_10cm;
  }
  return r;
}

}  // namespace yarnfit::pipeline
