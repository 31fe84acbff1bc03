#include "numerics/optim/brent_minimize.hpp"

#include <cmath>
#include <limits>

namespace yarnfit::numerics {

ScalarMinimum brent_minimize(const std::function<double(double)>& f, double lower, double upper, double tolerance,
                             int max_evaluations) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
  ScalarMinimum out;
  // Non-finite values order after every finite one.
  const auto value = [&](double x) {
    ++out.evaluations;
    const double v = f(x);
    return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
  };
  double a = lower, b = upper;
  double x = a + golden * (b - a), w = x, v = x;
  double fx = value(x), fw = fx, fv = fx;
  double d = 0.0, e = 0.0;  // the last step and the one before it
  while (out.evaluations < max_evaluations) {
    const double m = 0.5 * (a + b);
    const double tol1 = eps * std::abs(x) + tolerance / 3.0, tol2 = 2.0 * tol1;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) {
      out.converged = true;
      break;
    }
    bool parabolic = false;
    if (std::abs(e) > tol1 && std::isfinite(fx) && std::isfinite(fw) && std::isfinite(fv)) {
      // The parabola through (v, fv), (w, fw), (x, fx); its vertex at x + p/q.
      double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      else q = -q;
      const double e_before = e;
      // Trusted when it lies inside the bracket and moves less than half the step before last.
      if (std::abs(p) < std::abs(0.5 * q * e_before) && p > q * (a - x) && p < q * (b - x)) {
        e = d;
        d = p / q;
        parabolic = true;
        if ((x + d) - a < tol2 || b - (x + d) < tol2) d = x < m ? tol1 : -tol1;
      }
    }
    if (!parabolic) {
      e = (x < m ? b : a) - x;
      d = golden * e;
    }
    const double u = x + (std::abs(d) >= tol1 ? d : (d > 0.0 ? tol1 : -tol1));
    const double fu = value(u);
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw;
      w = x, fw = fx;
      x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw;
        w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  out.x = x;
  out.value = fx;
  return out;
}

}  // namespace yarnfit::numerics
