#pragma once
// The tile a yarn model was fitted on, drawn for the report (issue 48), so a user sees at a
// glance whether it is their knit: from above (2 × 2 periods, the weft to the right, the warp
// up) and from the side (2 periods along the weft, looking along the warp). Each yarn is drawn
// in its colour at the given radius, segment by segment from the farthest to the nearest (so
// the crossings show which yarn lies over which) and darker the farther it lies; the period is
// outlined. Inline SVG, nothing fetched, no script.

#include <string>

#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::reports {

struct TileDrawing {
  std::string above;  // SVG elements, empty when the tile cannot be drawn
  std::string side;
};

// `id` makes the drawings' clip paths unique on the page; `attributes` go on both <svg>s.
// A tile that is not closed loops (compute_tile_facts throws) gives empty drawings.
TileDrawing draw_tile(const db::PeriodicTile& tile, double radius, const std::string& id, const std::string& attributes);

}  // namespace yarnfit::reports
