#pragma once
// The knitting gauge a tile shows (issue 48): its wales and courses in one period, and per
// 10 cm as fabric specifications state them (SPEC §2 `knitting_gauge`), so that a user can
// see beside their record whether the tile the yarn model was fitted on is their knit.
//
// A tile generated from a chart knows its counts (the chart's). A tile given as a file is
// counted from its yarns, as a weft knit is built: every course is one yarn running along the
// weft (net offset along the weft axis alone), and each of its stitches raises one loop head,
// a maximum of the warp coordinate along the yarn. Maxima are counted with a hysteresis of
// half a course spacing, so the wiggles of a sinker loop or of a tuck do not count. Tiles that
// are not weft knits (a weave, a yarn running along the warp, courses that disagree) have no
// count.

#include <optional>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::db {

struct TileGauge {
  int wales = 0;    // in one period, across the weft axis' length
  int courses = 0;  // in one period, along the warp axis
  double wale_spacing = 0.0;    // [m]
  double course_spacing = 0.0;  // [m]
  [[nodiscard]] double wales_per_10cm() const { return 0.1 / wale_spacing; }
  [[nodiscard]] double courses_per_10cm() const { return 0.1 / course_spacing; }
};

// The gauge of a tile whose period holds `wales` × `courses` stitches (a chart's).
TileGauge gauge_of_counts(const PeriodicTile& tile, Axis weft_axis, int wales, int courses);

// The gauge counted from the tile's yarns, or nothing when it is not a weft knit (see above).
std::optional<TileGauge> count_knit_gauge(const PeriodicTile& tile, const TileFacts& facts, Axis weft_axis);

}  // namespace yarnfit::db
