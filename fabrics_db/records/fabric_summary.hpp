#pragma once
// Machine-readable descriptions of fabrics for `yarnfit db show` and `db list` (SPEC §5).
// Values are SI; key names carry their unit (_m, _N, _N_per_m, _kg_per_m2).

#include <nlohmann/json.hpp>

#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::db {

// Line forces bounding the comfort and power ranges: 2 N and 5 N on the thesis's 6 cm
// swatch (SPEC §3), stated per unit width so that swatches of any width compare.
inline constexpr double k_comfort_line_force = 2.0 / 0.06;  // 33.3 N/m
inline constexpr double k_power_line_force = 5.0 / 0.06;    // 83.3 N/m

// Stretch at which the test's line force first reaches `line_force` (linear
// interpolation), or nullopt when the measured curve stays below it.
std::optional<double> stretch_at_line_force(const StretchTest& test, double line_force);

nlohmann::json describe_tile(const PeriodicTile& tile, const TileFacts& facts);
nlohmann::json describe_fabric(const Fabric& fabric);
// One row of `db list`: id, family, folder, validity, tests present.
nlohmann::json list_entry(const FabricLoad& load);

}  // namespace yarnfit::db
