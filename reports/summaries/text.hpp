#pragma once
// Number formatting shared by the text reports (internal to reports/summaries).

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "fabrics_db/text_util.hpp"

namespace yarnfit::reports {

// "12.3 %" with 3 significant digits, "-" when there is no figure.
inline std::string pct(double v) { return std::isfinite(v) ? db::format_g(v, 3) + " %" : std::string("-"); }

// A JSON number with `digits` significant digits, "-" when it is not a number.
inline std::string number_text(const nlohmann::json& v, int digits = 4) {
  return v.is_number() ? db::format_g(v.get<double>(), digits) : std::string("-");
}

// A number with `digits` significant digits, "-" when there is none (NaN).
inline std::string number_text(double v, int digits = 4) {
  return std::isfinite(v) ? db::format_g(v, digits) : std::string("-");
}

}  // namespace yarnfit::reports
