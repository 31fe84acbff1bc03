#include "yarn_fit/fit/problem/yarn_fit_problem.hpp"

#include <omp.h>

#include <numbers>
#include <stdexcept>

#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::yarn {

bool check_yarn_stiffness(const db::Fabric& fabric, db::Problems& problems) {
  if (fabric.stiffest_yarn_stiffness()) return true;
  problems.add((fabric.folder / db::k_fabric_file_name).string(), 0, "yarns.stiffness_N",
               "missing; a yarn fit needs the stiffest yarn's stretch stiffness (sets ks2, SPEC §3)");
  return false;
}

std::optional<YarnFitProblem> make_yarn_fit_problem(const db::Fabric& fabric, db::Problems& problems) {
  const std::size_t before = problems.size();
  const std::string yaml = (fabric.folder / db::k_fabric_file_name).string();
  const auto stiffness = fabric.stiffest_yarn_stiffness();
  if (!fabric.pattern)
    problems.add(yaml, 0, "pattern",
                 "missing; a yarn fit needs the periodic yarn tile (pattern: {file: tile.pyp, weft_axis: x})");
  check_yarn_stiffness(fabric, problems);
  if (fabric.pattern && !fabric.pattern->has_tile())
    problems.add(yaml, 0, "pattern.knit",
                 "the tile of this knit is not made yet: yarnfit fit and batch generate it (or make it with yarnfit "
                 "tile make and name it with pattern: {file: ...})");
  if (problems.size() != before) return std::nullopt;
  YarnFitProblem problem;
  problem.fabric_id = fabric.id;
  problem.family = fabric.family;
  problem.hold_period = fabric.pattern->knit && fabric.pattern->knit->gauge;
  // A generated tile was relaxed with contact radius R1 = the knit's yarn radius (its yarns
  // rest pressed into each other, so its geometric R_est is smaller): the bounds are centred
  // on the radius it was made with, which the generation's parameters then lie inside.
  problem.scales = {*stiffness, fabric.pattern->knit ? fabric.pattern->knit->yarn_radius : fabric.pattern->facts.r_est};
  const std::string pyp = fabric.pattern->file.string();
  try {
    problem.tile = yarn::make_yarn_tile(fabric.pattern->tile);
  } catch (const std::exception& e) {
    problems.add(pyp, 0, "pattern", e.what());
    return std::nullopt;
  }
  // The objective pulls along the tile's x axis for weft: turn a tile whose weft runs along y.
  if (fabric.pattern->weft_axis == db::Axis::y) problem.tile = yarn::rotated_tile(problem.tile, -std::numbers::pi / 2.0);
  if (!(problem.scales.r_est > 0.0)) problems.add(pyp, 0, "pattern", "no contact radius R_est could be computed");
  if (problems.size() != before) return std::nullopt;
  return problem;
}

void read_start(YarnFitProblem& problem, const std::filesystem::path& file, bool linear_stretch,
                db::Problems& problems) {
  db::Problems found;
  problem.start = yarn::read_yarn_params(file, problem.scales, found);
  problems.append(found);
  if (!problem.start) return;
  const auto space = yarn_parameter_space(problem.scales, linear_stretch);
  for (const std::string& outside : space.bounds_problems(point_from_params(*problem.start, linear_stretch))) {
    // "R1: 0.004 is outside the search bounds [...]": the key, then what is wrong with it.
    const auto colon = outside.find(": ");
    problems.add(file.string(), 0, outside.substr(0, colon), outside.substr(colon + 2) + " of this fabric");
  }
}

YarnFitSettings settings_for(const YarnFitProblem& problem, YarnFitSettings settings) {
  if (problem.start) {
    settings.start = problem.start;
    settings.swarm = false;
  }
  if (problem.hold_period) settings.objective.rest.period_chord_steps = 0;
  return settings;
}

YarnFitResult fit_yarn(const YarnFitProblem& problem, const YarnFitSettings& settings) {
  const YarnFitSettings s = settings_for(problem, settings);
  if (s.threads > 0) omp_set_num_threads(s.threads);
  return fit_yarn_params(problem.tile, problem.targets, problem.scales, s);
}

results::YarnFitFile to_file(const YarnFitProblem& problem, const YarnFitResult& result, const YarnFitSettings& settings) {
  results::YarnFitFile f = to_file(result, settings_for(problem, settings));
  f.fabric = problem.fabric_id;
  f.family = problem.family;
  f.targets = problem.targets_source;
  return f;
}

}  // namespace yarnfit::yarn
