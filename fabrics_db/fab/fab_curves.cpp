#include "fabrics_db/fab/fab_curves.hpp"
#include "numerics/util/non_finite.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace yarnfit::db {
namespace {

using numerics::k_nan;

struct Branch {
  std::vector<double> x, f;  // x ascending
};

// Linear interpolation inside [x.front(), x.back()] (the caller checks the range).
double at(const Branch& b, double x) {
  const auto hi = static_cast<std::size_t>(std::upper_bound(b.x.begin(), b.x.end(), x) - b.x.begin());
  if (hi == 0) return b.f.front();
  if (hi >= b.x.size()) return b.f.back();
  const double t = (x - b.x[hi - 1]) / (b.x[hi] - b.x[hi - 1]);
  return (1.0 - t) * b.f[hi - 1] + t * b.f[hi];
}

// A stretch test's loading branch in stretch: s ≥ 0, advancing, force ≥ 0 after the zero.
Branch stretch_branch(const FabTest& test, const FabBranchCurve& b, int& dropped) {
  Branch out;
  const double zero = test.zero_offset.value_or(0.0);
  for (std::size_t i = 0; i < b.clamp_distance.size(); ++i) {
    const double s = b.clamp_distance[i] / test.clamp_distance - 1.0;
    if (s < 0.0) continue;  // slack: the strip takes no load yet
    const double f = b.raw_force[i] - zero;
    if (f < 0.0 || (!out.x.empty() && s <= out.x.back())) {
      ++dropped;
      continue;
    }
    out.x.push_back(s);
    out.f.push_back(f);
  }
  return out;
}

bool compared(const FabTest& test, double d) {
  const double L = test.clamp_distance;
  return test.kind == FabTestKind::stretch ? d >= L : d > 0.3 * L && d < 0.999 * L;
}

// A branch in clamp distance over the compared range, sorted ascending (ties dropped).
Branch distance_branch(const FabTest& test, const FabBranchCurve& b, double offset) {
  std::vector<std::pair<double, double>> p;
  for (std::size_t i = 0; i < b.clamp_distance.size(); ++i)
    if (compared(test, b.clamp_distance[i])) p.emplace_back(b.clamp_distance[i], b.raw_force[i] - offset);
  std::stable_sort(p.begin(), p.end(), [](const auto& a, const auto& c) { return a.first < c.first; });
  Branch out;
  for (const auto& [x, f] : p)
    if (out.x.empty() || x > out.x.back()) {
      out.x.push_back(x);
      out.f.push_back(f);
    }
  return out;
}

// ∫ f dx along the samples in the order measured (signed), and ∫ |f| |dx|, over the compared
// range.
std::pair<double, double> path_work(const FabTest& test, const FabBranchCurve& b, double offset) {
  double w = 0.0, size = 0.0;
  for (std::size_t i = 1; i < b.clamp_distance.size(); ++i)
    if (compared(test, b.clamp_distance[i - 1]) && compared(test, b.clamp_distance[i])) {
      const double f = 0.5 * (b.raw_force[i - 1] + b.raw_force[i] - 2.0 * offset);
      const double dx = b.clamp_distance[i] - b.clamp_distance[i - 1];
      w += f * dx;
      size += std::abs(f * dx);
    }
  return {w, size};
}

}  // namespace

StretchCurve fab_stretch_curve(const FabTest& test, int& dropped) {
  dropped = 0;
  std::vector<Branch> branches;
  for (const auto& b : test.branches)
    if (b.branch == FabBranch::loading) {
      Branch s = stretch_branch(test, b, dropped);
      if (!s.x.empty()) branches.push_back(std::move(s));
    }
  StretchCurve c;
  if (branches.empty()) return c;
  const auto widest = std::max_element(branches.begin(), branches.end(),
                                       [](const Branch& a, const Branch& b) { return a.x.back() < b.x.back(); });
  for (std::size_t i = 0; i < widest->x.size(); ++i) {
    const double s = widest->x[i];
    double sum = 0.0;
    int n = 0;
    for (const auto& b : branches)
      if (s >= b.x.front() && s <= b.x.back()) {
        sum += at(b, s);
        ++n;
      }
    c.stretch.push_back(s);
    c.force.push_back(sum / n);  // n ≥ 1: the widest branch covers its own points
  }
  return c;
}

FabCycleFigures fab_cycle_figures(const FabTest& test, double offset) {
  FabCycleFigures out;
  std::vector<Branch> loading;
  double hysteresis = 0.0;
  int cycles = 0;
  for (const auto& b : test.branches) {
    if (b.branch != FabBranch::loading) continue;
    Branch d = distance_branch(test, b, offset);
    if (d.x.size() >= 2) loading.push_back(std::move(d));
    // The cycle's relaxation branch, when the record has it.
    const auto r = std::find_if(test.branches.begin(), test.branches.end(), [&b](const FabBranchCurve& c) {
      return c.cycle == b.cycle && c.branch == FabBranch::relaxation;
    });
    if (r == test.branches.end()) continue;
    // The loop's area over the loading work, taken without sign (a bend's force may cross zero).
    const auto [load_work, load_size] = path_work(test, b, offset);
    if (load_size == 0.0) continue;
    hysteresis += std::abs(load_work + path_work(test, *r, offset).first) / load_size;
    ++cycles;
  }
  out.loading_branches = static_cast<int>(loading.size());
  out.hysteresis_pct = cycles > 0 ? 100.0 * hysteresis / cycles : k_nan;
  // Spread on the union of the branches' distances where two or more overlap: the sum of the
  // ranges over the sum of the mean forces' sizes (a ratio of sums, so that points where the
  // force passes zero do not blow it up).
  double spread = 0.0, size = 0.0;
  for (const auto& grid : loading)
    for (const double x : grid.x) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0.0;
      int n = 0;
      for (const auto& b : loading)
        if (x >= b.x.front() && x <= b.x.back()) {
          const double f = at(b, x);
          lo = std::min(lo, f);
          hi = std::max(hi, f);
          sum += f;
          ++n;
        }
      if (n < 2) continue;
      spread += hi - lo;
      size += std::abs(sum / n);
    }
  out.spread_pct = size > 0.0 ? 100.0 * spread / size : k_nan;
  return out;
}

}  // namespace yarnfit::db
