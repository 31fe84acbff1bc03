#include "numerics/util/format.hpp"

#include <cstdio>

namespace yarnfit::numerics {

std::string format_number(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace yarnfit::numerics
