#include "fabrics_db/import/tensile_import.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"

namespace yarnfit::db {

namespace fs = std::filesystem;

ColumnRef ColumnRef::parse(const std::string& text) {
  ColumnRef ref;
  const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return c >= '0' && c <= '9';
  });
  if (digits) ref.index = std::stoi(text);
  else ref.name = text;
  return ref;
}

std::string ColumnRef::describe() const {
  return index > 0 ? "column " + std::to_string(index) : "column '" + name + "'";
}

std::optional<ForceUnit> parse_force_unit(const std::string& text) {
  if (text == "N") return ForceUnit::N;
  if (text == "cN") return ForceUnit::cN;
  if (text == "mN") return ForceUnit::mN;
  if (text == "kN") return ForceUnit::kN;
  return std::nullopt;
}

std::optional<ExtensionUnit> parse_extension_unit(const std::string& text) {
  if (text == "mm") return ExtensionUnit::mm;
  if (text == "stretch") return ExtensionUnit::stretch;
  return std::nullopt;
}

namespace {

double newtons_per(ForceUnit u) {
  switch (u) {
    case ForceUnit::N: return 1.0;
    case ForceUnit::cN: return 1e-2;
    case ForceUnit::mN: return 1e-3;
    case ForceUnit::kN: return 1e3;
  }
  return 1.0;
}

std::vector<ColumnRef> referenced_columns(const TensileImportOptions& o) {
  std::vector<ColumnRef> refs{o.extension, o.force};
  if (o.width) refs.push_back(*o.width);
  if (o.compression) refs.push_back(*o.compression);
  return refs;
}

// The delimiter that splits `line` into the most fields.
char detect_delimiter(const std::string& line) {
  char best = ',';
  std::size_t most = 0;
  for (char d : {',', ';', '\t'}) {
    const auto n = split_csv_line(line, d).size();
    if (n > most) {
      most = n;
      best = d;
    }
  }
  return best;
}

// Finds the header: the first line holding every column referenced by name (so a
// metadata block above it is skipped), or the first non-empty line if all are by index.
std::optional<int> find_header_line(const std::vector<std::string>& lines,
                                    const TensileImportOptions& o, char& delimiter) {
  std::vector<std::string> names;
  for (const auto& r : referenced_columns(o)) {
    if (r.index == 0) names.push_back(r.name);
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view body = trim(lines[i]);
    if (body.empty() || body.front() == '#') continue;
    const char d = o.delimiter.value_or(detect_delimiter(lines[i]));
    const auto cells = split_csv_line(lines[i], d);
    const bool all = std::all_of(names.begin(), names.end(), [&](const std::string& n) {
      return std::find(cells.begin(), cells.end(), n) != cells.end();
    });
    if (all) {
      delimiter = d;
      return static_cast<int>(i);
    }
  }
  return std::nullopt;
}

}  // namespace

TensileImportResult import_tensile(const TensileImportOptions& o) {
  TensileImportResult result;
  Problems& problems = result.problems;
  const std::string in_label = o.input.string();

  // Options that cannot work, before reading anything.
  if (o.extension_unit == ExtensionUnit::mm && !(o.gauge_length_mm && *o.gauge_length_mm > 0))
    problems.add(in_label, 0, "--gauge-length-mm",
                 "extension in mm needs the initial length between clamps or marks (> 0)");
  if (o.width && !(o.swatch_width_mm && *o.swatch_width_mm > 0))
    problems.add(in_label, 0, "--swatch-width-mm",
                 "a width column needs the unstretched swatch width (> 0) to give compression");
  if (o.width && o.compression)
    problems.add(in_label, 0, "--compression-col", "give either a width or a compression column, not both");
  std::error_code ec;
  if (fs::exists(o.output, ec) && fs::equivalent(o.input, o.output, ec))
    problems.add(o.output.string(), 0, "--out", "output would replace the input file");
  else if (fs::exists(o.output, ec) && !o.overwrite)
    problems.add(o.output.string(), 0, "--out", "file exists; pass --force to replace it");
  if (!problems.empty()) return result;

  std::string text;
  if (std::string why; !read_text_file(o.input, text, why)) {
    problems.add(in_label, 0, "file", why);
    return result;
  }
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      lines.push_back(line);
    }
  }
  char delimiter = o.delimiter.value_or(',');
  int skip = 0;
  if (o.skip_lines) {
    skip = *o.skip_lines;
    for (int i = skip; i < static_cast<int>(lines.size()); ++i) {
      if (!trim(lines[static_cast<std::size_t>(i)]).empty()) {
        delimiter = o.delimiter.value_or(detect_delimiter(lines[static_cast<std::size_t>(i)]));
        break;
      }
    }
  } else if (const auto header = find_header_line(lines, o, delimiter)) {
    skip = *header;
  } else {
    std::vector<std::string> names;
    for (const auto& r : referenced_columns(o)) names.push_back(r.describe());
    problems.add(in_label, 0, "header",
                 "no line holds all of " + join_words(names, " and ") +
                     "; check the column names or give --skip-lines");
    return result;
  }
  const auto table = parse_csv(text, in_label, CsvOptions{delimiter, skip}, problems);
  if (!table) return result;

  // Resolve column references against the header.
  auto resolve = [&](const ColumnRef& ref, const char* option) -> std::optional<std::size_t> {
    if (ref.index > 0) {
      if (static_cast<std::size_t>(ref.index) <= table->header.size())
        return static_cast<std::size_t>(ref.index - 1);
      problems.add(in_label, table->header_line, option,
                   ref.describe() + " does not exist: the header has " +
                       std::to_string(table->header.size()) + " columns");
      return std::nullopt;
    }
    if (const auto c = table->column(ref.name)) return static_cast<std::size_t>(*c);
    problems.add(in_label, table->header_line, option,
                 "no " + ref.describe() + "; columns found: " + join_words(table->header, ", "));
    return std::nullopt;
  };
  const auto c_ext = resolve(o.extension, "--stretch-col");
  const auto c_force = resolve(o.force, "--force-col");
  std::optional<std::size_t> c_width, c_comp;
  if (o.width) c_width = resolve(*o.width, "--width-col");
  if (o.compression) c_comp = resolve(*o.compression, "--compression-col");
  if (!problems.empty()) return result;

  // Convert every row; cell problems name the input line and its column header.
  struct Row {
    int line;
    double s, f, c;
  };
  std::vector<Row> rows;
  for (const auto& row : table->rows) {
    ++result.rows_read;
    bool ok = true;
    auto cell = [&](std::size_t col) -> double {
      const std::string field = col < table->header.size() ? table->header[col] : "column " + std::to_string(col + 1);
      if (col >= row.cells.size()) {
        problems.add(in_label, row.line, field, "missing value");
        ok = false;
        return 0.0;
      }
      std::string why;
      const auto v = parse_finite_number(row.cells[col], why);
      if (!v) {
        problems.add(in_label, row.line, field, why);
        ok = false;
        return 0.0;
      }
      return *v;
    };
    Row r{row.line, cell(*c_ext), cell(*c_force) * newtons_per(o.force_unit), std::nan("")};
    if (o.extension_unit == ExtensionUnit::mm) r.s /= *o.gauge_length_mm;
    if (c_width) r.c = 1.0 - cell(*c_width) / *o.swatch_width_mm;
    if (c_comp) r.c = cell(*c_comp);
    if (ok) rows.push_back(r);
  }
  if (!problems.empty()) return result;

  if (o.loading_branch && !rows.empty()) {
    // Up to the first peak force, then only rows that extend the stretch.
    const auto peak = std::max_element(rows.begin(), rows.end(),
                                       [](const Row& a, const Row& b) { return a.f < b.f; });
    std::vector<Row> kept;
    for (auto it = rows.begin(); it <= peak; ++it) {
      if (kept.empty() || it->s > kept.back().s) kept.push_back(*it);
    }
    result.rows_dropped = rows.size() - kept.size();
    rows = std::move(kept);
  }

  // Check with the rules of a fabric's own curves, reporting against the input lines.
  CsvTable converted;
  converted.file_label = in_label;
  converted.header_line = table->header_line;
  converted.header = {"stretch", "force_N"};
  const bool with_c = c_width || c_comp;
  if (with_c) converted.header.push_back("compression");
  for (const auto& r : rows) {
    CsvRow out{r.line, {format_g(r.s, 10), format_g(r.f, 10)}};
    if (with_c) out.cells.push_back(format_g(r.c, 10));
    converted.rows.push_back(out);
  }
  auto curve = read_stretch_curve(converted, problems);
  if (!curve) return result;

  std::ostringstream csv;
  csv << "# imported by yarnfit db import-tensile from " << o.input.filename().string() << "\n";
  csv << "# extension: " << o.extension.describe()
      << (o.extension_unit == ExtensionUnit::mm ? " in mm over " + format_g(*o.gauge_length_mm) + " mm" : " as stretch")
      << "; force: " << o.force.describe() << "\n";
  for (std::size_t i = 0; i < converted.header.size(); ++i) csv << (i ? "," : "") << converted.header[i];
  csv << "\n";
  for (const auto& r : converted.rows) {
    for (std::size_t i = 0; i < r.cells.size(); ++i) csv << (i ? "," : "") << r.cells[i];
    csv << "\n";
  }
  try {
    write_text_file_atomically(o.output, csv.str());
  } catch (const std::exception& e) {
    problems.add(o.output.string(), 0, "--out", e.what());
    return result;
  }
  result.written = true;
  result.rows_written = converted.rows.size();
  result.curve = std::move(*curve);
  return result;
}

}  // namespace yarnfit::db
