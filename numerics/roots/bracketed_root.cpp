#include "numerics/roots/bracketed_root.hpp"
#include "numerics/util/error.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace yarnfit::numerics {

namespace {

// The secant-guided step: 10 % past the secant's root, its length kept within ¼ to 4 times
// the doubling step, in the step's direction. (Until issue 17 this was written for upward
// searches only, min(max(v, ¼·step), 4·step), which for a downward search always gave 4·step:
// going down, a secant pointing the same way quadrupled the step whatever its length.)
double limited_secant_step(double to_root, double step) {
  const double length = std::clamp(std::abs(1.1 * to_root), 0.25 * std::abs(step), 4.0 * std::abs(step));
  return std::copysign(length, step);
}

}  // namespace

Problems RootFindOptions::problems() const {
  Problems out;
  if (std::isnan(lower) || std::isnan(upper) || !(lower <= upper)) out.add_field("lower, upper", "lower ≤ upper required");
  if (!(initial_step > 0.0) || !std::isfinite(initial_step)) out.add_field("initial_step", "must be positive and finite");
  if (!(initial_slope >= 0.0) || !std::isfinite(initial_slope)) out.add_field("initial_slope", "must be finite and ≥ 0");
  if (!(x_tolerance >= 0.0) || !std::isfinite(x_tolerance)) out.add_field("x_tolerance", "must be finite and ≥ 0");
  if (!(f_tolerance >= 0.0) || !std::isfinite(f_tolerance)) out.add_field("f_tolerance", "must be finite and ≥ 0");
  if (max_evaluations < 1) out.add_field("max_evaluations", "must be ≥ 1");
  return out;
}

const char* to_string(RootStatus status) {
  switch (status) {
    case RootStatus::converged: return "converged";
    case RootStatus::not_bracketed: return "not_bracketed";
    case RootStatus::evaluation_failed: return "evaluation_failed";
    case RootStatus::evaluation_limit: return "evaluation_limit";
  }
  return "unknown";
}

RootResult find_root(const RootFunction& f, double guess, const RootFindOptions& o) {
  if (const Problems problems = o.problems(); !problems.empty())
    throw Error(ErrorCategory::input, "find_root: " + problems.one_line());
  RootResult out;
  const auto evaluate = [&](double x) {
    ++out.evaluations;
    const std::optional<double> v = f(x);
    out.x = x;
    out.f = v ? *v : std::numeric_limits<double>::quiet_NaN();
    return v;
  };
  const auto finish = [&](RootStatus status) {
    out.status = status;
    return out;
  };

  double a = std::clamp(guess, o.lower, o.upper);
  const auto first = evaluate(a);
  if (!first) return finish(RootStatus::evaluation_failed);
  double fa = *first;
  if (std::abs(fa) <= o.f_tolerance) return finish(RootStatus::converged);

  // f increasing: the root lies above a when f(a) < 0.
  double step = o.initial_slope > 0.0 && std::isfinite(fa) ? -fa / o.initial_slope
                                                           : o.initial_step * (fa < 0.0 ? 1.0 : -1.0);
  double b = a, fb = fa;
  bool bracketed = false;
  while (out.evaluations < o.max_evaluations) {
    // After two evaluations on one side, aim the next one past the secant's root.
    if (b != a && fb != fa && std::isfinite(fa) && std::isfinite(fb)) {
      const double to_root = -fb * (b - a) / (fb - fa);
      if (to_root * step > 0.0) step = limited_secant_step(to_root, step);
    }
    const double next = std::clamp(b + step, o.lower, o.upper);
    if (next == b) break;
    a = b;
    fa = fb;
    b = next;
    const auto vb = evaluate(b);
    if (!vb) return finish(RootStatus::evaluation_failed);
    fb = *vb;
    if ((fa < 0.0) != (fb < 0.0) || std::abs(fb) <= o.f_tolerance) {
      bracketed = true;
      break;
    }
    step *= 2.0;
  }
  if (!bracketed) return finish(out.evaluations >= o.max_evaluations ? RootStatus::evaluation_limit : RootStatus::not_bracketed);

  // Illinois inside [a, b]: regula falsi keeps one end, whose value is halved when it is kept
  // twice in a row, so the bracket shrinks from both sides.
  int side = 0;
  double fc = fb;
  double previous = b;
  while (out.evaluations < o.max_evaluations && std::abs(b - a) > o.x_tolerance && std::abs(fc) > o.f_tolerance) {
    const double c = std::isfinite(fa) && std::isfinite(fb) ? (a * fb - b * fa) / (fb - fa) : 0.5 * (a + b);
    // Regula falsi keeps one end of the bracket: stop once the iterate itself settles.
    if (std::abs(c - previous) <= 0.1 * o.x_tolerance) break;
    previous = c;
    const auto vc = evaluate(c);
    if (!vc) return finish(RootStatus::evaluation_failed);
    fc = *vc;
    if ((fc < 0.0) == (fb < 0.0)) {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c;
      fa = fc;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
    if (fc == 0.0) break;
  }
  if (std::abs(b - a) > o.x_tolerance && std::abs(fc) > o.f_tolerance && out.evaluations >= o.max_evaluations)
    return finish(RootStatus::evaluation_limit);
  return finish(RootStatus::converged);
}

}  // namespace yarnfit::numerics
