#pragma once
// A container's index from the int the solvers count elements and vertices with.
#include <cstddef>

namespace yarnfit::numerics {

inline std::size_t idx(int i) { return static_cast<std::size_t>(i); }

}  // namespace yarnfit::numerics
