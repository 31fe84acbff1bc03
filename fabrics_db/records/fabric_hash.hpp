#pragma once
// The fingerprint of one fabric's job: SHA-256 over the record (fabric.yaml), every file it
// names (stretch and bending curves, the tile, wherever they live) and the fit options. The
// same inputs give the same hash on any machine; a changed byte anywhere, a renamed file or a
// changed option gives another, and the batch fits the fabric again.

#include <string>

#include <nlohmann/json.hpp>

#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::db {

// For a valid record, its fabric.yaml and the files it names; for an invalid one (which
// names no usable files), every file in its folder. Unreadable files count by their name
// and the reason they cannot be read.
[[nodiscard]] std::string fabric_hash(const db::FabricLoad& load, const nlohmann::json& options);

}  // namespace yarnfit::db
