#pragma once
// The terminal line of `yarnfit batch` (SPEC §5: stage, time left), e.g.
//   batch: 2/5 done, 1 failed, running A2 (swarm 3/10), B1 (shell), 1 queued, 42 s, about 3.5 min left

#include <string>

#include "batch/batch_options.hpp"

namespace yarnfit::cli {

[[nodiscard]] std::string batch_progress_line(const batch::BatchProgress& p);
// "42 s", "3.5 min", "2.1 h"
[[nodiscard]] std::string duration_text(double seconds);

}  // namespace yarnfit::cli
