#include "shell_fit/fit/fab_record_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <omp.h>

namespace yarnfit::shell {

namespace {

// The FAB work's OpenMP threads held to the stage's `threads` while it runs: a loop's mesh is
// small, and a job given one thread that started two-thread teams for each assembly crawled
// beside other work (its teams' barriers waiting on a descheduled thread).
class ThreadsHeld {
 public:
  explicit ThreadsHeld(int threads) : m_previous(omp_get_max_threads()) { omp_set_num_threads(std::max(1, threads)); }
  ~ThreadsHeld() { omp_set_num_threads(m_previous); }
  ThreadsHeld(const ThreadsHeld&) = delete;
  ThreadsHeld& operator=(const ThreadsHeld&) = delete;

 private:
  int m_previous;
};

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

void check_fab_held_out(const std::vector<std::string>& held_out, const char* field, db::Problems& problems) {
  const auto say = [&](const std::string& message) { problems.add("", 0, field, message); };
  int stretch = 0, bends = 0;
  for (std::size_t i = 0; i < held_out.size(); ++i) {
    const auto* spec = db::find_fab_test(held_out[i]);
    if (!spec) {
      say(held_out[i] + ": not a FAB test (S1, S2, U1, D1, D2)");
      continue;
    }
    if (std::find(held_out.begin(), held_out.begin() + static_cast<std::ptrdiff_t>(i), held_out[i]) !=
        held_out.begin() + static_cast<std::ptrdiff_t>(i)) {
      say(held_out[i] + ": named twice");
      continue;
    }
    (spec->kind == db::FabTestKind::stretch ? stretch : bends) += 1;
  }
  if (stretch != 1)
    say("must hold out exactly one of S1 and S2 (the in-plane fit takes one stretch test per direction; got " +
        std::to_string(stretch) + ")");
  if (bends == 3) say("holds out every bend (U1, D1, D2): k_θ would not be fitted");
}

db::Fabric fab_fit_view(const db::Fabric& fabric, const std::vector<std::string>& held_out) {
  db::Fabric view = fabric;
  view.stretch_tests.clear();
  for (const auto& [dir, tests] : fabric.fab_tests)
    for (const auto& t : tests) {
      if (t.kind != db::FabTestKind::stretch || contains(held_out, t.name)) continue;
      db::StretchTest s;
      s.direction = dir;
      s.file = t.file;
      s.swatch = {t.clamp_distance, t.strip_width};
      int dropped = 0;
      s.curve = db::fab_stretch_curve(t, dropped);
      if (s.curve.size() >= 2) view.stretch_tests[dir] = std::move(s);
    }
  return view;
}

std::vector<FabBendFit> fit_fab_record_bends(const db::Fabric& fabric, const InplaneParams& inplane,
                                             const std::vector<std::string>& held_out, int threads,
                                             const FabBendOptions& options) {
  std::vector<std::pair<db::Direction, std::vector<const db::FabTest*>>> work;
  for (const auto& [dir, tests] : fabric.fab_tests) {
    std::vector<const db::FabTest*> fitted;
    for (const auto& t : tests)
      if (t.kind != db::FabTestKind::stretch && !contains(held_out, t.name)) fitted.push_back(&t);
    if (!fitted.empty()) work.emplace_back(dir, std::move(fitted));
  }
  std::vector<FabBendFit> fits(work.size());
  const ThreadsHeld held(threads);
  const double rho = fabric.areal_density.value_or(0.0);
#pragma omp parallel for num_threads(std::max(1, threads)) schedule(dynamic)
  for (std::size_t i = 0; i < work.size(); ++i) fits[i] = fit_fab_bends(work[i].second, work[i].first, inplane, rho, options);
  return fits;
}

std::vector<FabTestFigure> fab_test_figures(const db::Fabric& fabric, const ShellParams& params,
                                            const std::vector<FabBendFit>& bends,
                                            const std::vector<std::string>& held_out, int threads,
                                            const FabStretchOptions& stretch, const FabBendOptions& bend) {
  std::vector<std::pair<db::Direction, const db::FabTest*>> tests;
  for (const auto& [dir, list] : fabric.fab_tests)
    for (const auto& t : list) tests.emplace_back(dir, &t);
  std::vector<FabTestFigure> out(tests.size());
  const ThreadsHeld held(threads);
  const double rho = fabric.areal_density.value_or(0.0);
#pragma omp parallel for num_threads(std::max(1, threads)) schedule(dynamic)
  for (std::size_t i = 0; i < tests.size(); ++i) {
    const db::Direction dir = tests[i].first;  // not a structured binding: lambdas capture it
    const auto& t = tests[i].second;
    FabTestFigure& f = out[i];
    f.direction = dir;
    f.held_out = contains(held_out, t->name);
    if (t->kind == db::FabTestKind::stretch) {
      f.error = predict_fab_stretch(*t, dir, params.inplane, stretch);
    } else {
      const auto fit = std::find_if(bends.begin(), bends.end(), [dir](const FabBendFit& b) { return b.direction == dir; });
      const FabTestError* found = nullptr;
      if (!f.held_out && fit != bends.end())
        for (const auto& e : fit->tests)
          if (e.test == t->name) found = &e;
      if (found) {
        f.error = *found;
      } else if (params.bending.ktheta[static_cast<std::size_t>(dir)] > 0.0) {
        f.error = predict_fab_bend(*t, dir, params, rho, bend);
      } else {
        f.error.test = t->name;
        f.error.force_pct = f.error.first_cycles_force_pct = f.error.mean_abs_error = f.error.offset =
            std::numeric_limits<double>::quiet_NaN();
        f.error.message = "k_θ of this direction not fitted";
      }
    }
    // The measurement's own figures about its zero; a bend's about the model's offset, or
    // about no offset when the model failed.
    f.cycles = db::fab_cycle_figures(*t, std::isfinite(f.error.offset) ? f.error.offset : 0.0);
    if (!std::isfinite(f.error.offset)) f.cycles.spread_pct = f.cycles.hysteresis_pct = std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

}  // namespace yarnfit::shell
