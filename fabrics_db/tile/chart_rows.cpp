#include "fabrics_db/tile/chart_rows.hpp"

namespace yarnfit::db {

std::optional<std::vector<std::string>> split_chart_rows(const std::string& text, const std::string& symbols,
                                                         const std::string& kind, const std::string& given,
                                                         const std::string& cells, std::string& why) {
  std::vector<std::string> rows(1);
  for (const char c : text) {
    if (c == '/') rows.emplace_back();
    else if (symbols.find(c) != std::string::npos) rows.back() += c;
    else if (c != ' ') {
      why = "unknown";
      return std::nullopt;
    }
  }
  for (std::size_t j = 0; j < rows.size(); ++j) {
    if (rows[j].empty()) {
      why = kind + " '" + given + "': row " + std::to_string(j + 1) + " has no " + cells;
      return std::nullopt;
    }
    if (rows[j].size() != rows.front().size()) {
      why = kind + " '" + given + "': row " + std::to_string(j + 1) + " has " + std::to_string(rows[j].size()) + " " +
            cells + ", row 1 has " + std::to_string(rows.front().size()) +
            " (every row of a repeating chart has the same width)";
      return std::nullopt;
    }
  }
  return rows;
}

}  // namespace yarnfit::db
