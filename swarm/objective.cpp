#include "swarm/objective.hpp"

#include <cmath>
#include <exception>
#include <sstream>

namespace yarnfit::swarm {

Evaluation evaluate_guarded(const std::function<double()>& f) noexcept {
  Evaluation e;
  try {
    const double v = f();
    if (std::isfinite(v)) {
      e.value = v;
      e.ok = true;
    } else {
      e.message = std::isnan(v) ? "objective returned NaN" : (v > 0 ? "objective returned +inf" : "objective returned -inf");
    }
  } catch (const std::exception& ex) {
    try {
      e.message = std::string("objective threw: ") + ex.what();
    } catch (...) {
      // Out of memory while copying the message: the failure is still counted.
    }
  } catch (...) {
    try {
      e.message = "objective threw an exception not derived from std::exception";
    } catch (...) {
    }
  }
  return e;
}

}  // namespace yarnfit::swarm
