#include "numerics/roots/bisection.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace yarnfit::numerics {

double midpoint(double lower, double upper, Midpoint rule) {
  return rule == Midpoint::geometric ? std::sqrt(lower * upper) : 0.5 * (lower + upper);
}

std::string BisectionOptions::problem() const {
  if (halvings < 0) return "halvings must be ≥ 0";
  if (!(relative_width >= 0.0) || !std::isfinite(relative_width)) return "relative_width must be finite and ≥ 0";
  return {};
}

BisectionResult bisect(const SidePredicate& below, double lower, double upper, const BisectionOptions& o) {
  if (const std::string why = o.problem(); !why.empty()) throw Error(ErrorCategory::input, "bisect: " + why);
  if (!(lower <= upper)) throw Error(ErrorCategory::input, "bisect: lower ≤ upper required");
  if (o.midpoint == Midpoint::geometric && !(lower > 0.0))
    throw Error(ErrorCategory::input, "bisect: a geometric midpoint needs a positive bracket");
  BisectionResult out;
  for (int k = 0; k < o.halvings && (o.relative_width == 0.0 || upper - lower > o.relative_width * upper); ++k) {
    const double m = midpoint(lower, upper, o.midpoint);
    const std::optional<bool> side = below(m);
    if (!side) {
      out.evaluation_failed = true;
      break;
    }
    (*side ? lower : upper) = m;
    ++out.halvings;
  }
  out.lower = lower;
  out.upper = upper;
  out.x = midpoint(lower, upper, o.midpoint);
  return out;
}

std::string FactorBracketOptions::problem() const {
  if (!(lower > 0.0) || !std::isfinite(upper) || !(lower <= upper)) return "0 < lower ≤ upper < inf required";
  if (!(factor > 1.0) || !std::isfinite(factor)) return "factor must be finite and > 1";
  return {};
}

FactorBracket bracket_by_factor(const SidePredicate& below, double start, const FactorBracketOptions& o) {
  if (const std::string why = o.problem(); !why.empty()) throw Error(ErrorCategory::input, "bracket_by_factor: " + why);
  FactorBracket out;
  double x = std::clamp(start, o.lower, o.upper);
  while (true) {
    ++out.evaluations;
    const std::optional<bool> side = below(x);
    if (!side) {
      out.failed_at = x;
      break;
    }
    if (*side) {
      out.below = x;
      if (out.above || x >= o.upper) break;
      x = std::min(o.factor * x, o.upper);
    } else {
      out.above = x;
      if (out.below || x <= o.lower) break;
      x = std::max(x / o.factor, o.lower);
    }
  }
  return out;
}

}  // namespace yarnfit::numerics
