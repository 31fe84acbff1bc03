#include "fabrics_db/tile/chart_rows.hpp"

namespace yarnfit::db {

ChartRows split_chart_rows(const std::string& text, const std::string& symbols, const std::string& kind,
                           const std::string& given, const std::string& cells) {
  ChartRows out;
  std::vector<std::string> rows(1);
  for (const char c : text) {
    if (c == '/') rows.emplace_back();
    else if (symbols.find(c) != std::string::npos) rows.back() += c;
    else if (c != ' ') {
      out.unknown_symbol = true;
      return out;
    }
  }
  for (std::size_t j = 0; j < rows.size(); ++j) {
    if (rows[j].empty()) {
      out.problem = kind + " '" + given + "': row " + std::to_string(j + 1) + " has no " + cells;
      return out;
    }
    if (rows[j].size() != rows.front().size()) {
      out.problem = kind + " '" + given + "': row " + std::to_string(j + 1) + " has " + std::to_string(rows[j].size()) +
                    " " + cells + ", row 1 has " + std::to_string(rows.front().size()) +
                    " (every row of a repeating chart has the same width)";
      return out;
    }
  }
  out.rows = std::move(rows);
  return out;
}

}  // namespace yarnfit::db
