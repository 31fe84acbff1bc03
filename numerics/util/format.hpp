#pragma once
// Numbers in messages: printf's "%.<digits>g", short and unambiguous about magnitude.

#include <string>

namespace yarnfit::numerics {

// `v` to `digits` significant digits, e.g. 0.000123 → "0.000123", 1.5e-08 → "1.5e-08".
[[nodiscard]] std::string format_number(double v, int digits = 3);

}  // namespace yarnfit::numerics
