#pragma once
// A small CSV reader that keeps the source line of every row, so problems can point at it.
// Blank lines and lines starting with '#' are skipped; the first other line is the header.
// Fields may be double-quoted ("a,b" and "" for a quote). Surrounding spaces are trimmed.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabrics_db/problems.hpp"

namespace yarnfit::db {

struct CsvRow {
  int line = 0;  // 1-based line in the file
  std::vector<std::string> cells;
};

struct CsvTable {
  std::string file_label;  // path as shown in problems
  int header_line = 0;
  std::vector<std::string> header;
  std::vector<CsvRow> rows;

  // Index of the column named `name`, if present.
  [[nodiscard]] std::optional<int> column(std::string_view name) const;
};

struct CsvOptions {
  char delimiter = ',';
  int skip_lines = 0;  // physical lines dropped before looking for the header
};

// Splits one line into fields (quotes honoured, spaces trimmed).
std::vector<std::string> split_csv_line(std::string_view line, char delimiter);

// Parses CSV text. A problem is recorded when there is no header line.
std::optional<CsvTable> parse_csv(const std::string& text, const std::string& file_label,
                                  const CsvOptions& options, Problems& problems);
// Reads a file; an unreadable file is one problem (line 0, field "file").
std::optional<CsvTable> read_csv(const std::filesystem::path& file, const CsvOptions& options,
                                 Problems& problems);

// Parses a finite decimal number (no NaN, no Inf, nothing after it). On failure returns
// nullopt and sets `why` to a message fit for a problem report.
std::optional<double> parse_finite_number(std::string_view text, std::string& why);

}  // namespace yarnfit::db
