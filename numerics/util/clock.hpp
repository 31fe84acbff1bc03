#pragma once
// The one clock of run times: steady (never steps back with the wall clock), read as seconds.

#include <chrono>

namespace yarnfit::numerics {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace yarnfit::numerics
