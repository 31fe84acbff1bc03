#pragma once
// The shell stage on a FAB record (issue 51; docs/fab.md): which of its tests the fit takes
// and which it holds out, the in-plane fit's view of the record, k_θ per direction from the
// fitted loop bends, and every test, fitted or held out, compared with the fitted model.
//
// The in-plane fit takes one stretch curve per direction, so exactly one of the 2 cm (S1) and
// 8 cm (S2) stretch tests is held out; by default S1, whose short, wide gauge then tests the
// model where the clamps' restraint matters. Any of the bends (U1, D1, D2) may be held out as
// long as one is fitted.

#include <string>
#include <vector>

#include "fabrics_db/fab/fab_curves.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/fit/fab_fit.hpp"

namespace yarnfit::shell {

inline const std::vector<std::string> k_default_fab_held_out{"S1"};

// Every problem of a held-out list (field `field`): names that are no FAB test, repeats, not
// exactly one stretch test, every bend.
void check_fab_held_out(const std::vector<std::string>& held_out, const char* field, db::Problems& problems);

// The fabric as the in-plane fit sees it: each direction's stretch test the mean loading
// curve (db::fab_stretch_curve) of its FAB stretch test not held out, at that test's gauge.
[[nodiscard]] db::Fabric fab_fit_view(const db::Fabric& fabric, const std::vector<std::string>& held_out);

// One FAB test against the fitted model.
struct FabTestFigure {
  db::Direction direction = db::Direction::weft;
  bool held_out = false;
  FabTestError error;       // every loading branch (a bend: its offset the best one)
  db::FabCycleFigures cycles;  // the measurement's spread over cycles and its hysteresis
};

struct FabRecordFit {
  std::vector<std::string> held_out;
  std::vector<FabBendFit> bends;      // one per direction with a fitted bend
  std::vector<FabTestFigure> tests;   // every test of every direction, in the record's order
  double seconds = 0.0;
};

// k_θ of each direction from its bends not held out, directions in parallel on `threads`.
[[nodiscard]] std::vector<FabBendFit> fit_fab_record_bends(const db::Fabric& fabric, const InplaneParams& inplane,
                                                           const std::vector<std::string>& held_out, int threads,
                                                           const FabBendOptions& options = {});

// Every test of the record against `params`: the stretch tests predicted, the fitted bends'
// errors as `bends` found them, the held-out bends predicted. Tests in parallel on `threads`.
[[nodiscard]] std::vector<FabTestFigure> fab_test_figures(const db::Fabric& fabric, const ShellParams& params,
                                                          const std::vector<FabBendFit>& bends,
                                                          const std::vector<std::string>& held_out, int threads,
                                                          const FabStretchOptions& stretch = {},
                                                          const FabBendOptions& bend = {});

}  // namespace yarnfit::shell
