#include "fabrics_db/csv/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::db {

std::optional<int> CsvTable::column(std::string_view name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  return std::nullopt;
}

std::vector<std::string> split_csv_line(std::string_view line, char delimiter) {
  std::vector<std::string> cells;
  std::string cell;
  bool in_quotes = false;
  bool was_quoted = false;
  std::size_t quoted_end = 0;  // length of the quoted text; spaces after the closing quote drop
  auto finish = [&] {
    if (in_quotes) {  // a quote left open: the cell holds the rest of the line, as quoted
      quoted_end = cell.size();
      in_quotes = false;
    }
    cells.push_back(was_quoted ? cell.substr(0, quoted_end) + std::string(trim(cell.substr(quoted_end)))
                               : std::string(trim(cell)));
    cell.clear();
    was_quoted = false;
  };
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
        quoted_end = cell.size();
      } else {
        cell += c;
      }
    } else if (c == '"' && trim(cell).empty()) {
      in_quotes = true;
      was_quoted = true;
      quoted_end = 0;
      cell.clear();
    } else if (c == delimiter) {
      finish();
    } else {
      cell += c;
    }
  }
  finish();
  return cells;
}

std::optional<CsvTable> parse_csv(const std::string& text, const std::string& file_label,
                                  const CsvOptions& options, Problems& problems) {
  CsvTable table;
  table.file_label = file_label;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    if (line_no <= options.skip_lines) continue;
    const std::string_view body = trim(line);
    if (body.empty() || body.front() == '#') continue;
    auto cells = split_csv_line(line, options.delimiter);
    if (table.header_line == 0) {
      table.header_line = line_no;
      table.header = std::move(cells);
    } else {
      table.rows.push_back(CsvRow{line_no, std::move(cells)});
    }
  }
  if (table.header_line == 0) {
    problems.add(file_label, 0, "header", "no header line: the file has no CSV content");
    return std::nullopt;
  }
  return table;
}

std::optional<CsvTable> read_csv(const std::filesystem::path& file, const CsvOptions& options,
                                 Problems& problems) {
  std::string text;
  if (std::string why; !read_text_file(file, text, why)) {
    problems.add(file.string(), 0, "file", why);
    return std::nullopt;
  }
  return parse_csv(text, file.string(), options, problems);
}

std::optional<double> parse_finite_number(std::string_view text, std::string& why) {
  const std::string_view s = trim(text);
  if (s.empty()) {
    why = "missing value";
    return std::nullopt;
  }
  // from_chars does not take a leading '+'.
  const std::string_view digits = (s.front() == '+') ? s.substr(1) : s;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    why = "value '" + std::string(s) + "' is out of range";
    return std::nullopt;
  }
  if (ec != std::errc() || ptr != digits.data() + digits.size()) {
    why = "expected a number, got '" + std::string(s) + "'";
    return std::nullopt;
  }
  if (std::isnan(value)) {
    why = "NaN is not a valid value";
    return std::nullopt;
  }
  if (std::isinf(value)) {
    why = "infinite value '" + std::string(s) + "'";
    return std::nullopt;
  }
  return value;
}

}  // namespace yarnfit::db
