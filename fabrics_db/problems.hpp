#pragma once
// The readers' name for numerics::Problems (numerics/problems.hpp): problems found in user
// input, collected rather than thrown so that one run reports every problem of every file.

#include "numerics/problems.hpp"

namespace yarnfit::db {

using Problem = numerics::Problem;
using Problems = numerics::Problems;

}  // namespace yarnfit::db
