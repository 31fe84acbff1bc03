#pragma once
// Reading and validating fabric records (SPEC §2). Validation reports every problem it
// finds, never only the first, and never writes to the user's files.

#include <filesystem>
#include <optional>
#include <string>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::db {

inline constexpr const char* k_fabric_file_name = "fabric.yaml";

// The outcome of reading one fabric folder.
struct FabricLoad {
  std::filesystem::path folder;
  std::string id;      // best effort, also when invalid (for listings); may be empty
  std::string family;  // best effort
  int id_line = 0;     // line of the id key in fabric.yaml, 0 if absent
  std::optional<Fabric> fabric;  // present only when `problems` is empty
  Problems problems;

  [[nodiscard]] bool ok() const { return fabric.has_value() && problems.empty(); }
};

// True when `folder` holds a fabric.yaml.
bool is_fabric_folder(const std::filesystem::path& folder);

// Reads `folder`/fabric.yaml, its curves and its tile, and validates all of them.
FabricLoad load_fabric(const std::filesystem::path& folder);

// Curve readers, shared with the tensile importer. Columns: stretch, force_N and optional
// compression; or clamp_distance_mm and aspect_ratio. Extra columns are ignored.
std::optional<StretchCurve> read_stretch_curve(const CsvTable& table, Problems& problems);
std::optional<BendingCurve> read_bending_curve(const CsvTable& table, Problems& problems);
// A FAB test's samples (fab_tests): cycle, branch (loading or relaxation), clamp_distance_mm,
// raw_force_N; consecutive rows of one cycle and branch make one branch.
std::optional<std::vector<FabBranchCurve>> read_fab_test_curve(const CsvTable& table, Problems& problems);

// Fewest data rows a curve may have: one point defines no curve.
inline constexpr std::size_t k_min_curve_points = 2;

}  // namespace yarnfit::db
