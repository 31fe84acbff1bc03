#pragma once
// Uniform targets: the hand-off from the shell stage to the yarn stage (thesis 6.3, eq. 6.3;
// SPEC §1 steps 2–3). shell_fit generates them from a fitted shell model
// (shell_fit/targets/uniform_targets.hpp); the yarn calibration fits yarn parameters to them.
// Both stages link fabrics_db, so neither links the other for these types.
//
// Per direction (weft 0°, bias 45°, warp 90°), for a pull along u at angle φ from the weft
// (v ⟂ u) and F(s, c) = (1 + s) u uᵀ + (1 − c) v vᵀ:
//   stretch rows  s, the zero-orthogonal-stress compression c*(s), σ_s = uᵀ P(F(s, c*)) u
//                 (first Piola-Kirchhoff, N/m per reference width);
//   bending rows  κ [1/m] and σ_κ = 2 k_θ κ [N].
//
// The file, uniform_targets.csv:
//   direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N
// kind "stretch" or "bending"; cells that do not apply to a row's kind are empty; numbers
// with 10 significant digits. Blank lines and '#' lines are skipped when reading.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::db {

struct UniaxialPoint {
  double stretch = 0.0;
  double compression = 0.0;  // zero-orthogonal-stress compression c*
  double stress = 0.0;       // σ_s [N/m]
  bool converged = false;    // the 1-D minimisation met its tolerance (the reader sets true)
};

struct BendingPoint {
  double curvature = 0.0;  // κ [1/m]
  double stress = 0.0;     // σ_κ = 2 k_θ κ [N]
};

struct DirectionTargets {
  Direction direction = Direction::weft;
  std::vector<UniaxialPoint> stretch;  // empty when the direction has no stretch range
  std::vector<BendingPoint> bending;   // empty when it has no curvature range
};

// The text of uniform_targets.csv for these targets.
std::string uniform_targets_csv(const std::vector<DirectionTargets>& targets);
// Writes that text to `file` atomically. Throws an Error naming the file.
void write_uniform_targets_csv(const std::vector<DirectionTargets>& targets, const std::filesystem::path& file);

// The targets as uniform_targets.csv holds them: every number rounded to the file's 10
// significant digits exactly as writing and reading it back would (the same text, parsed by
// the reader's own conversion). A yarn fit on these is the fit on the file, bit for bit, so
// the pipeline can hand its targets over in memory. `converged` is kept.
std::vector<DirectionTargets> as_stored(const std::vector<DirectionTargets>& targets);

// Reads the file. Every problem is added as `file:line: field: message` (missing column,
// unknown direction or kind, non-numeric or non-finite cell, stretch not strictly increasing
// within a direction, fewer than 2 stretch rows for a direction that has any). Directions
// come out in weft, bias, warp order, only those present; every point has converged = true.
// Empty result when any problem was found.
std::optional<std::vector<DirectionTargets>> read_uniform_targets(const std::filesystem::path& file,
                                                                 Problems& problems);

// As above; throws an input Error whose what() lists every problem, one per line.
std::vector<DirectionTargets> read_uniform_targets(const std::filesystem::path& file);

// The targets of `direction`, or nullptr.
const DirectionTargets* find_direction(const std::vector<DirectionTargets>& targets, Direction direction);

}  // namespace yarnfit::db
