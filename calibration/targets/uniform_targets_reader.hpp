#pragma once
// Reader of uniform_targets.csv, the file shell_fit writes (shell/targets/uniform_targets.hpp,
// write_uniform_targets_csv) and the yarn calibration reads (SPEC §1 step 3, §5):
//
//   direction,kind,stretch,compression,stress_s_N_per_m,curvature_per_m,stress_kappa_N
//
// kind "stretch": stretch s, zero-orthogonal-stress compression c*, σ_s = uᵀ P u (first
// Piola-Kirchhoff, N/m per reference width); kind "bending": curvature κ [1/m], σ_κ [N]. Cells
// that do not apply to a row's kind are empty. Blank lines and '#' lines are skipped.
//
// The result uses shell_fit's own types, so the writer and the reader round-trip.

#include <filesystem>
#include <optional>
#include <vector>

#include "fabrics_db/problems.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::calibration {

using shell::DirectionTargets;

// Reads the file. Every problem is added as `file:line: field: message` (missing column,
// unknown direction or kind, non-numeric or non-finite cell, stretch not strictly increasing
// within a direction, fewer than 2 stretch rows for a direction that has any). Directions
// come out in weft, bias, warp order, only those present; every point has converged = true.
// Empty result when any problem was found.
std::optional<std::vector<DirectionTargets>> read_uniform_targets(const std::filesystem::path& file,
                                                                 db::Problems& problems);

// As above; throws std::invalid_argument whose what() lists every problem, one per line.
std::vector<DirectionTargets> read_uniform_targets(const std::filesystem::path& file);

// The targets of `direction`, or nullptr.
const DirectionTargets* find_direction(const std::vector<DirectionTargets>& targets, db::Direction direction);

}  // namespace yarnfit::calibration
