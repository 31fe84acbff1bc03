#pragma once
// The row layout the knit and weave charts share: rows separated by '/', spaces ignored, one
// symbol per cell, every row as wide as the first (the chart repeats).

#include <string>
#include <vector>

namespace yarnfit::db {

struct ChartRows {
  std::vector<std::string> rows;  // each a string of its cells; empty when a problem was found
  bool unknown_symbol = false;    // a character neither '/', a space nor a symbol: the caller words it
  std::string problem;            // an empty row or one of another width ("<kind> '<given>': row 2 has 3 <cells>, …")
  [[nodiscard]] bool ok() const { return !unknown_symbol && problem.empty(); }
};

ChartRows split_chart_rows(const std::string& text, const std::string& symbols, const std::string& kind,
                           const std::string& given, const std::string& cells);

}  // namespace yarnfit::db
