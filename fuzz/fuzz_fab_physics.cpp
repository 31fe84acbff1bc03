// A FAB physics file (JSON), as `db import --format fab` and the service's FAB upload read it:
// parse_fab_physics lists every problem with its JSON path and never throws.
#include "fabrics_db/fab/fab_physics.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(fab_physics) {
  using namespace yarnfit;
  const db::FabRead r = db::parse_fab_physics(fuzz::as_text(data, size), "physics.json");
  if (r.measurement && !r.problems.empty()) fuzz::finding("fab_physics: a result beside problems");
  if (r.measurement)
    for (const auto& [direction, tests] : r.measurement->tests)
      for (const auto& test : tests) (void)db::estimate_zero_offset(test);
  return 0;
}
