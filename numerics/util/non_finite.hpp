#pragma once
// The two non-finite doubles the code writes by name: an unbounded limit and "no value".
#include <limits>

namespace yarnfit::numerics {

inline constexpr double k_inf = std::numeric_limits<double>::infinity();
inline constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

}  // namespace yarnfit::numerics
