#pragma once

namespace yarnfit::results {

// A parameter's search range, as shell_fit.json's and yarn_fit.json's `bounds` hold it.
struct SearchBound {
  double lower = 0.0;
  double upper = 0.0;
  bool log = true;  // searched in log space
};

}  // namespace yarnfit::results
