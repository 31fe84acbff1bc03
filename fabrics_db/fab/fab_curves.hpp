#pragma once
// What a FAB test's cycles say beside their samples (docs/fab.md): the loading curve the
// shell fit takes from a stretch test, the spread of its cycles about it, and the hysteresis
// between each cycle's loading and relaxation branches.
//
// The FAB's cycles are progressive, not repeats of one path: each reaches further than the one
// before. So a stretch test's curve is, at each stretch, the mean of the loading branches that
// reach it (one branch far out, all of them near the start), and the spread is how far apart
// the branches lie where two or more overlap.

#include <vector>

#include "fabrics_db/records/fab_test.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::db {

// The stretch curve a FAB stretch test gives the fit: at the stretches s = d/length − 1 ≥ 0 of
// its widest loading branch, the mean force of the loading branches that reach s, the zero
// offset taken off. Within a branch, samples that do not advance the stretch or read below zero
// are left out (counted in `dropped`).
StretchCurve fab_stretch_curve(const FabTest& test, int& dropped);

struct FabCycleFigures {
  int loading_branches = 0;
  // Where two or more loading branches overlap: Σ (max − min) / Σ |mean| over those points
  // [%]; NaN when no two overlap.
  double spread_pct = 0.0;
  // Mean over the cycles with both branches of the area between loading and relaxation over
  // ∫ |force| |d distance| of loading [%]; NaN when no cycle has both.
  double hysteresis_pct = 0.0;
};

// The figures of `test`, the force read less `offset` [N] (its zero offset, or a bend's fitted
// one), over the clamp distances the fit compares (a stretch test's past its taut length, a
// bend's between 0.3 and 0.999 of it).
FabCycleFigures fab_cycle_figures(const FabTest& test, double offset);

}  // namespace yarnfit::db
