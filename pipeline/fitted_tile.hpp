#pragma once
// yarn_fit.json's `tile` (issue 48): the tile the yarn model was fitted on, described as a
// knitter reads it — where it came from, its period, its wales and courses per 10 cm (the
// chart's counts for a generated knit, counted from the yarns for a tile given as a file:
// fabrics_db/tile/knit_gauge.hpp) — beside the record's own knitting_gauge, so the report and
// the summaries can show whether it is the user's knit.

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "results/yarn_fit_file.hpp"

namespace yarnfit::pipeline {

// `shape_fitted`: the tile came out of the shape search (yarn_fit/fit/problem/shape_search.hpp);
// `shape_held`: its period was held at a fitted aspect (false: the generated tile's own won).
results::FittedTileRecord describe_fitted_tile(const db::Fabric& fabric, const db::PeriodicTile& tile, bool shape_fitted,
                                               bool shape_held);

}  // namespace yarnfit::pipeline
