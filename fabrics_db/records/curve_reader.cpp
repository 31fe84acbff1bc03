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

std::optional<std::vector<FabBranchCurve>> read_fab_test_curve(const CsvTable& table, Problems& problems) {
  const std::size_t before = problems.size();
  const std::vector<ColumnSpec> specs{{"cycle", true}, {"branch", true}, {"clamp_distance_mm", true}, {"raw_force_N", true}};
  const auto columns = find_columns(table, specs, problems);
  if (problems.size() != before) return std::nullopt;
  if (!enough_rows(table, problems)) return std::nullopt;

  // Numbers only for the numeric columns; the branch is a word.
  const std::vector<ColumnSpec> numeric{specs[0], specs[2], specs[3]};
  const std::vector<std::optional<int>> numeric_columns{columns[0], columns[2], columns[3]};
  std::vector<FabBranchCurve> branches;
  std::vector<double> v;
  for (const auto& row : table.rows) {
    bool ok = read_row(table, row, numeric, numeric_columns, v, problems);
    const auto col = static_cast<std::size_t>(*columns[1]);
    const std::string word = col < row.cells.size() ? std::string(trim(row.cells[col])) : "";
    const auto branch = parse_fab_branch(word);
    if (!branch) {
      problems.add(table.file_label, row.line, "branch", "'" + word + "': expected loading or relaxation");
      ok = false;
    }
    if (ok && (v[0] < 1.0 || v[0] != std::floor(v[0]) || v[0] > 1000.0)) {
      problems.add(table.file_label, row.line, "cycle", "expected a cycle number 1, 2, …, got " + format_g(v[0]));
      ok = false;
    }
    if (ok && v[1] <= 0.0) {
      problems.add(table.file_label, row.line, "clamp_distance_mm", "clamp distance must be positive, got " + format_g(v[1]));
      ok = false;
    }
    if (!ok) continue;
    const int cycle = static_cast<int>(v[0]);
    if (branches.empty() || branches.back().cycle != cycle || branches.back().branch != *branch) {
      for (const auto& b : branches)
        if (b.cycle == cycle && b.branch == *branch)
          problems.add(table.file_label, row.line, "cycle",
                       "cycle " + std::to_string(cycle) + " " + std::string(to_string(*branch)) +
                           " again after other rows: a branch's rows must be together");
      branches.push_back({cycle, *branch, {}, {}, {}});
    }
    branches.back().clamp_distance.push_back(v[1] * 1e-3);
    branches.back().raw_force.push_back(v[2]);
    branches.back().source_lines.push_back(row.line);
  }
  for (const auto& b : branches)
    if (b.clamp_distance.size() < k_min_curve_points)
      problems.add(table.file_label, b.source_lines.front(), "data",
                   "cycle " + std::to_string(b.cycle) + " " + std::string(to_string(b.branch)) +
                       " has one sample; a branch needs at least " + std::to_string(k_min_curve_points));
  if (problems.size() != before) return std::nullopt;
  return branches;
}

}  // namespace yarnfit::db
