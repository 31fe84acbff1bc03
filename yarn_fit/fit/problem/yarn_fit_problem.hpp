#pragma once
// A yarn fit of one fabric as a problem the calibration can run (SPEC §3 "Parameters", §5
// `yarnfit yarn fit`): what a fabric record and its uniform targets become before any
// simulation —
//   tile      the record's periodic tile, turned so that its weft runs along x (the
//             objective pulls along the tile's x axis for the weft);
//   scales    ks2 from the stiffest yarn's stiffness_N, R_est from the tile facts, or the
//             knit's yarn radius for a generated tile (they fix ks2, kc2, R2 and anchor the
//             bounds of the fitted parameters);
//   targets   the uniform targets, from uniform_targets.csv or handed over in memory;
//   start     optional parameters the local step starts from (--start), inside the bounds.
// Every problem found is listed at once, each naming its file and field; nothing runs then.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "yarn_fit/fit/yarn_fit.hpp"
#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/targets/uniform_targets.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::yarn {

struct YarnFitProblem {
  std::string fabric_id;
  std::string family;            // the record's family (reports group by it)
  yarn::YarnTile tile;           // weft along x
  yarn::ParameterScales scales;  // ks2 [N], R_est [m]
  std::vector<db::DirectionTargets> targets;
  std::string targets_source;    // where the targets came from (yarn_fit.json's `targets`)
  std::optional<yarn::YarnParams> start;  // the local step's start; the swarm is then skipped
  // The tile was generated at the record's knitting gauge: every rest state holds its period
  // (no period chord steps; the rest lengths and curvatures absorb the rest stress).
  bool hold_period = false;
};

// Adds a problem naming yarns.stiffness_N when `fabric` has no yarn stiffness (ks2 comes from
// it); true when it has one. Also checked before a knit's tile is generated.
bool check_yarn_stiffness(const db::Fabric& fabric, db::Problems& problems);

// The tile and scales of `fabric`: problems (added to `problems`) for a record without a
// pattern or a yarn stiffness, a tile the simulation cannot use, or no R_est. The targets
// are left empty. Empty result when anything is wrong.
std::optional<YarnFitProblem> make_yarn_fit_problem(const db::Fabric& fabric, db::Problems& problems);

// Reads the start parameters of `file` (a Y.yaml with yarn_fit.json's params keys, or a
// yarn_fit.json) into problem.start: the fixed ks2, kc2, R2 come from the fabric, and the
// optimised values must lie inside the bounds of these scales (with linear_stretch, ks1 and
// ε̄s are not fitted). Problems name the file and key.
void read_start(YarnFitProblem& problem, const std::filesystem::path& file, bool linear_stretch,
                db::Problems& problems);

// The settings the fit runs with: with a start, the local step alone from it; with a held
// period, rest states without period steps.
YarnFitSettings settings_for(const YarnFitProblem& problem, YarnFitSettings settings);

// Runs the calibration on the problem with settings_for(problem, settings) (calibration's
// fit_yarn_params; settings.threads > 0 also sets OpenMP's default team size). Throws
// an input Error for invalid settings or targets.
YarnFitResult fit_yarn(const YarnFitProblem& problem, const YarnFitSettings& settings);

// What yarn_fit.json holds: to_file(result, settings_for(problem, settings)) with the fabric's
// id and family and the targets' source.
results::YarnFitFile to_file(const YarnFitProblem& problem, const YarnFitResult& result, const YarnFitSettings& settings);

}  // namespace yarnfit::yarn
