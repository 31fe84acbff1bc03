#pragma once
// A fabric record as text, read from fabrics_db's JSON descriptions of it
// (fabrics_db/records/fabric_summary.hpp): what `db show` and `db list` print.

#include <iosfwd>

#include <string>

#include <nlohmann/json.hpp>

#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/import/tensile_import.hpp"

namespace yarnfit::reports {

// `db show` as text: composition, swatch, tests with curve ranges, tile facts.
void print_fabric(std::ostream& out, const nlohmann::json& fabric);
// `db list` as an aligned table.
void print_fabric_table(std::ostream& out, const nlohmann::json& entries);

// What an import wrote into `output`: `db import`'s and `db import-fab`'s summary.
[[nodiscard]] std::string tensile_import_text(const db::TensileImportResult& imported, const std::string& output);
[[nodiscard]] std::string fab_import_text(const db::FabImportResult& imported, const std::string& output);

}  // namespace yarnfit::reports
