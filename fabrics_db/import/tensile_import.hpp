#pragma once
// Turning a tensile-tester export into a stretch-test CSV (SPEC §2: stretch, force_N,
// compression). Rigs name their columns differently, give extension in millimetres,
// force in centinewtons and put a block of metadata above the header; the mapping says
// where each quantity is and in what unit. The result is checked with the same rules as a
// fabric's own curves before anything is written, and an existing file is never replaced
// unless `overwrite` is set.

#include <filesystem>
#include <optional>
#include <string>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::db {

// A column by header name, or by 1-based position when the text is all digits.
struct ColumnRef {
  std::string name;
  int index = 0;  // 1-based; 0 when referenced by name
  static ColumnRef parse(const std::string& text);
  [[nodiscard]] std::string describe() const;
};

enum class ExtensionUnit { mm, stretch };
enum class ForceUnit { N, cN, mN, kN };

struct TensileImportOptions {
  std::filesystem::path input;
  std::filesystem::path output;
  ColumnRef extension;                 // extension (mm) or stretch
  ColumnRef force;
  std::optional<ColumnRef> width;      // fabric width at mid-length [mm]
  std::optional<ColumnRef> compression;  // already dimensionless c
  ExtensionUnit extension_unit = ExtensionUnit::stretch;
  ForceUnit force_unit = ForceUnit::N;
  std::optional<double> gauge_length_mm;  // l̄, divides mm extensions
  std::optional<double> swatch_width_mm;  // w̄, turns widths into compression
  std::optional<int> skip_lines;  // lines before the header; found automatically when unset
  std::optional<char> delimiter;  // ',', ';' or tab; detected from the header when unset
  bool loading_branch = false;    // keep rows up to the peak force with increasing stretch
  bool overwrite = false;
};

struct TensileImportResult {
  bool written = false;
  std::size_t rows_read = 0;
  std::size_t rows_written = 0;
  std::size_t rows_dropped = 0;  // by loading_branch
  StretchCurve curve;
  Problems problems;  // input problems; nothing was written when non-empty
};

// Parses "N", "cN", "mN", "kN" and "mm", "stretch"; nullopt when unknown.
std::optional<ForceUnit> parse_force_unit(const std::string& text);
std::optional<ExtensionUnit> parse_extension_unit(const std::string& text);

TensileImportResult import_tensile(const TensileImportOptions& options);

}  // namespace yarnfit::db
