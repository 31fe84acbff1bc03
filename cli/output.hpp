#pragma once
// Human-readable rendering of fabrics_db's JSON descriptions.

#include <iosfwd>

#include <nlohmann/json.hpp>

namespace yarnfit::cli {

// `db show` as text: composition, swatch, tests with curve ranges, tile facts.
void print_fabric(std::ostream& out, const nlohmann::json& fabric);
// `db list` as an aligned table.
void print_fabric_table(std::ostream& out, const nlohmann::json& entries);

}  // namespace yarnfit::cli
