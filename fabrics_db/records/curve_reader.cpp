// CSV curves of stretch and bending tests, checked row by row.
#include <cmath>

#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"

namespace yarnfit::db {
namespace {

struct ColumnSpec {
  const char* name;
  bool required;
};

// Finds the columns of `specs` in the header; missing required columns become problems.
std::vector<std::optional<int>> find_columns(const CsvTable& table,
                                             const std::vector<ColumnSpec>& specs,
                                             Problems& problems) {
  std::vector<std::optional<int>> found;
  for (const auto& spec : specs) {
    found.push_back(table.column(spec.name));
    if (!found.back() && spec.required) {
      std::string hint;
      if (const auto near = closest_match(spec.name, table.header); !near.empty())
        hint = " (did you mean '" + near + "'?)";
      problems.add(table.file_label, table.header_line, spec.name,
                   "missing required column" + hint + "; columns found: " +
                       join_words(table.header, ", "));
    }
  }
  return found;
}

// Reads the numbers of one row for the given columns; problems name the row's line.
bool read_row(const CsvTable& table, const CsvRow& row, const std::vector<ColumnSpec>& specs,
              const std::vector<std::optional<int>>& columns, std::vector<double>& values,
              Problems& problems) {
  bool ok = true;
  values.assign(specs.size(), std::nan(""));
  for (std::size_t k = 0; k < specs.size(); ++k) {
    if (!columns[k]) continue;
    const auto col = static_cast<std::size_t>(*columns[k]);
    if (col >= row.cells.size()) {
      problems.add(table.file_label, row.line, specs[k].name,
                   "missing value (row has " + std::to_string(row.cells.size()) + " of " +
                       std::to_string(table.header.size()) + " columns)");
      ok = false;
      continue;
    }
    std::string why;
    if (const auto v = parse_finite_number(row.cells[col], why)) {
      values[k] = *v;
    } else {
      problems.add(table.file_label, row.line, specs[k].name, why);
      ok = false;
    }
  }
  return ok;
}

bool enough_rows(const CsvTable& table, Problems& problems) {
  if (table.rows.empty()) {
    problems.add(table.file_label, table.header_line, "data",
                 "header only: the file has no data rows");
    return false;
  }
  if (table.rows.size() < k_min_curve_points) {
    problems.add(table.file_label, table.rows.front().line, "data",
                 "only " + std::to_string(table.rows.size()) + " data row; a curve needs at least " +
                     std::to_string(k_min_curve_points));
    return false;
  }
  return true;
}

// Checks that `column` increases strictly from row to row.
void check_increasing(const CsvTable& table, const char* name, const std::vector<double>& values,
                      const std::vector<int>& lines, Problems& problems) {
  for (std::size_t i = 1; i < values.size(); ++i) {
    if (!(values[i] > values[i - 1])) {
      problems.add(table.file_label, lines[i], name,
                   "not strictly increasing: " + format_g(values[i]) + " follows " +
                       format_g(values[i - 1]) + " on line " + std::to_string(lines[i - 1]));
    }
  }
}

}  // namespace

std::optional<StretchCurve> read_stretch_curve(const CsvTable& table, Problems& problems) {
  const std::size_t before = problems.size();
  const std::vector<ColumnSpec> specs{{"stretch", true}, {"force_N", true}, {"compression", false}};
  const auto columns = find_columns(table, specs, problems);
  if (problems.size() != before) return std::nullopt;
  if (!enough_rows(table, problems)) return std::nullopt;

  StretchCurve curve;
  const bool with_compression = columns[2].has_value();
  std::vector<double> v;
  for (const auto& row : table.rows) {
    if (!read_row(table, row, specs, columns, v, problems)) continue;
    if (v[0] <= -1.0)
      problems.add(table.file_label, row.line, "stretch",
                   "stretch " + format_g(v[0]) + " would mean a length ≤ 0 (s = l/l̄ − 1 > −1)");
    if (v[1] < 0.0)
      problems.add(table.file_label, row.line, "force_N",
                   "negative force " + format_g(v[1]) + " N (tension is positive; tare the load cell)");
    if (with_compression && v[2] >= 1.0)
      problems.add(table.file_label, row.line, "compression",
                   "compression " + format_g(v[2]) + " would mean a width ≤ 0 (c = 1 − w/w̄ < 1)");
    curve.stretch.push_back(v[0]);
    curve.force.push_back(v[1]);
    if (with_compression) curve.compression.push_back(v[2]);
    curve.source_lines.push_back(row.line);
  }
  check_increasing(table, "stretch", curve.stretch, curve.source_lines, problems);
  if (problems.size() != before) return std::nullopt;
  return curve;
}

std::optional<BendingCurve> read_bending_curve(const CsvTable& table, Problems& problems) {
  const std::size_t before = problems.size();
  const std::vector<ColumnSpec> specs{{"clamp_distance_mm", true}, {"aspect_ratio", true}};
  const auto columns = find_columns(table, specs, problems);
  if (problems.size() != before) return std::nullopt;
  if (!enough_rows(table, problems)) return std::nullopt;

  BendingCurve curve;
  std::vector<double> v;
  for (const auto& row : table.rows) {
    if (!read_row(table, row, specs, columns, v, problems)) continue;
    if (v[0] <= 0.0)
      problems.add(table.file_label, row.line, "clamp_distance_mm",
                   "clamp distance must be positive, got " + format_g(v[0]));
    if (v[1] <= 0.0)
      problems.add(table.file_label, row.line, "aspect_ratio",
                   "aspect ratio h/p must be positive, got " + format_g(v[1]));
    curve.clamp_distance.push_back(v[0] * 1e-3);
    curve.aspect_ratio.push_back(v[1]);
    curve.source_lines.push_back(row.line);
  }
  std::vector<double> mm(curve.clamp_distance);
  for (double& d : mm) d *= 1e3;
  check_increasing(table, "clamp_distance_mm", mm, curve.source_lines, problems);
  if (problems.size() != before) return std::nullopt;
  return curve;
}

}  // namespace yarnfit::db
