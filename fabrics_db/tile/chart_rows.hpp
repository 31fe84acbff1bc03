#pragma once
// The row layout the knit and weave charts share: rows separated by '/', spaces ignored, one
// symbol per cell, every row as wide as the first (the chart repeats).

#include <optional>
#include <string>
#include <vector>

namespace yarnfit::db {

// The rows of `text`, each a string of its cells. Empty, with `why` set, when a character is
// neither '/', a space nor in `symbols` (why = "unknown", the caller words it), or when a row
// is empty or of another width than the first ("<kind> '<given>': row 2 has 3 <cells>, …").
std::optional<std::vector<std::string>> split_chart_rows(const std::string& text, const std::string& symbols,
                                                         const std::string& kind, const std::string& given,
                                                         const std::string& cells, std::string& why);

}  // namespace yarnfit::db
