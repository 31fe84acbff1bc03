#pragma once
// `yarnfit db import-fab`: a FAB measurement (fab_physics.hpp) written as a yarnfit record
// (docs/fab.md). The record keeps every test with its clamp distance, strip width, cycles and
// branches under `fab_tests` (fab/<direction>_<test>.csv, the load cell's readings in SI), the
// physics file unchanged as fab/physics.json (provenance, and what a U3M export gives back),
// mass per area and thickness; and, so that the fit can run on it now, each grain's 8 cm
// stretch (S2) as a `stretch_tests` curve: the mean of its loading branches
// (fab_curves.hpp), from the strip's taut length, the zero offset taken off. What the file
// does not say (the yarn's linear density, a knit or a tile for a yarn stage) comes from the
// options. The record is built in a hidden
// folder beside the destination and renamed into place: written whole or not at all.

#include <filesystem>
#include <optional>
#include <string>

#include "fabrics_db/fab/fab_physics.hpp"
#include "fabrics_db/problems.hpp"

namespace yarnfit::db {

struct FabImportOptions {
  std::filesystem::path input;   // .json, .u3m or .u3ma
  std::filesystem::path output;  // the record's folder; must not exist
  std::string id;                // default: the output folder's name
  std::string family;            // default: the file's category ("weaves", "knits"), else "fab"
  std::optional<double> denier;  // the yarn's linear density: required (the FAB does not measure it)
  std::string material;          // default: the file's composition
  // For a yarn stage, either a tile or a knit to generate one (SPEC §2 pattern):
  std::optional<std::filesystem::path> tile;  // copied into the record
  std::string knit;                           // a chart name, with the two below
  std::optional<double> stitch_length_mm, yarn_radius_mm;

  [[nodiscard]] Problems problems() const;
};

struct FabImportResult {
  bool written = false;
  Problems problems;  // input problems; nothing was written when non-empty
  std::optional<FabMeasurement> measurement;
  int stretch_points_dropped = 0;  // S2 samples left out of stretch_tests (not advancing, or below zero)
};

FabImportResult import_fab(const FabImportOptions& options);

}  // namespace yarnfit::db
