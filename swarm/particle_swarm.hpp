#pragma once
// Particle swarm optimiser (SPEC §1 step 4; thesis 6.5.3's global step): minimises a
// black-box objective over a box, with log-space parameters, evaluating the particles of an
// iteration in parallel (OpenMP). It knows nothing of yarns.
//
// The swarm moves in the unit cube of ParameterSpace. Iteration 1 evaluates the start
// positions (a Latin hypercube: one particle per 1/N slab of every coordinate, so even 64
// particles cover each range evenly; start velocities uniform in ±max_velocity); every
// later iteration k moves each particle i, then evaluates it:
//
//   v_i ← w_k v_i + c₁ r₁ ⊙ (p_i − x_i) + c₂ r₂ ⊙ (g − x_i) + a_i,   |v_i,c| ≤ v_max,
//   x_i ← clamp(x_i + v_i, 0, 1)   (a coordinate that hits a bound loses its velocity)
//
// p_i is the particle's best position, g the swarm's best, r₁ r₂ uniform in [0, 1) per
// coordinate, and the inertia w decays linearly from inertia_start (first move) to
// inertia_end (last move): broad exploration first, then convergence on the best basin.
//
// Repulsion a_i keeps the particles from collapsing onto g, where they would spend the
// remaining evaluations on one point. It is a soft short-range push, bounded as particles
// meet, zero beyond the radius r, and fading with the inertia:
//
//   a_i = (w_k / inertia_start) · s·r · Σ_{j≠i, 0<d_ij<r} (1 − d_ij/r)² · (x_i − x_j)/d_ij,
//   d_ij = ‖x_i − x_j‖
//
// r = repulsion_radius · N^(−1/d) (the spacing of N particles on a regular grid of the unit
// cube), s = repulsion_strength: the largest kick one neighbour gives, as a fraction of r.
// The fade keeps particles apart while the swarm explores and lets it contract on the best
// basin in the last iterations. On the benchmark table of tests/swarm a constant push left
// worse best values than the same push fading, and the fading default reaches the global
// minimum as often as no repulsion while keeping the particles further apart; a larger
// radius spreads them more but misses narrow basins (figures: docs/calibration.md). Raise
// repulsion_radius for objectives with several wide basins.
//
// Reproducible: every random number comes, serially, from one std::mt19937_64 seeded by
// `seed` with distributions written in random.hpp; particles are evaluated in parallel
// into a pre-sized array and reduced serially in particle order (ties keep the earlier
// particle). A run gives bitwise the same result with any number of threads, provided the
// objective itself is deterministic.
//
// Failed evaluations (throw, NaN, inf) count as +inf: they never become a particle's or
// the swarm's best; they are counted per iteration and their messages kept.
//
// Checkpoints: after every iteration the whole state (positions, velocities, bests, the
// engine's state, history) is written as JSON to a temporary file renamed over the
// checkpoint, so a kill at any moment leaves the last complete iteration on disk, and
// resume_swarm continues from it with bitwise the result of an uninterrupted run.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "swarm/objective.hpp"
#include "swarm/parameter_space.hpp"

namespace yarnfit::swarm {

// What the algorithm does; stored in the checkpoint, so a resumed run uses these.
struct SwarmSettings {
  int particles = 64;
  // Each evaluates every particle once: particles × iterations evaluations in all.
  int iterations = 10;
  double inertia_start = 0.9;
  double inertia_end = 0.1;
  // Pulls towards the particle's own best (cognitive) and the swarm's best (social).
  double cognitive = 1.5;
  double social = 1.5;
  // Largest velocity per coordinate, as a fraction of the range, per iteration.
  double max_velocity = 0.25;
  // Radius in units of N^(−1/d), strength as a fraction of the radius (formula above);
  // strength 0 turns repulsion off.
  double repulsion_radius = 0.25;
  double repulsion_strength = 0.5;
  std::uint64_t seed = 1;
  // Caller's coordinates of up to `particles` start points (a prior guess, say); they
  // replace the first particles' random start positions. Not stored in the checkpoint:
  // they only matter before the first checkpoint is written.
  std::vector<Eigen::VectorXd> initial_points;

  // Every setting out of range, under its field's name; empty when valid.
  [[nodiscard]] numerics::Problems problems() const;
};

// One iteration of the history.
struct IterationRecord {
  int iteration = 0;  // from 1
  // Best value found so far (this and all earlier iterations); +inf while none succeeded.
  double best_value = std::numeric_limits<double>::infinity();
  // Best and mean of this iteration's successful evaluations; +inf when all failed. Values
  // at or above their particle's own best may be lower bounds (ParticleContext::cutoff).
  double iteration_best = std::numeric_limits<double>::infinity();
  double mean_value = std::numeric_limits<double>::infinity();
  int failed = 0;        // failed evaluations in this iteration
  // Mean distance from each particle to its nearest neighbour, in the unit cube: how far
  // the swarm has contracted, and whether particles pile onto one point (repulsion's job).
  double neighbour_distance = 0.0;
  double inertia = 0.0;  // w of the move into this iteration (0 for iteration 1: no move)
  double seconds = 0.0;  // wall time of the iteration
};

// What the progress callback sees after each iteration (and its checkpoint).
struct SwarmProgress {
  const IterationRecord& record;
  int iterations = 0;                  // planned in all
  const Eigen::VectorXd& best_point;   // caller's coordinates; empty while none succeeded
  int evaluations = 0;
  int failed = 0;
  double seconds = 0.0;       // since the run started, including runs before a resume
  double seconds_left = 0.0;  // estimate from this run's mean time per iteration
};
// Return false to stop after this iteration (its checkpoint is already written).
using SwarmCallback = std::function<bool(const SwarmProgress&)>;

// How this run executes; does not change its result.
struct SwarmRunOptions {
  int threads = 0;  // OpenMP threads evaluating particles; 0: OpenMP's default
  // Written after every iteration; empty: none (resume_swarm then keeps writing to the
  // checkpoint it resumed from).
  std::filesystem::path checkpoint;
  SwarmCallback progress;
  int max_failures_kept = 50;  // failed evaluations whose message the summary keeps
};

enum class SwarmStatus {
  completed,  // all iterations done
  stopped,    // the progress callback asked to stop; resume from the checkpoint
};
[[nodiscard]] const char* to_string(SwarmStatus status);

struct SwarmSummary {
  SwarmStatus status = SwarmStatus::completed;
  Eigen::VectorXd best_point;  // caller's coordinates; empty when every evaluation failed
  double best_value = std::numeric_limits<double>::infinity();
  int best_iteration = 0;  // where best_point was evaluated
  int best_particle = -1;
  std::vector<IterationRecord> history;
  // Each particle's best position (caller's coordinates) and value (+inf while it has none): the
  // distinct good points a multi-start search goes on from. Restored with the run on resume.
  std::vector<Eigen::VectorXd> particle_best_points;
  std::vector<double> particle_best_values;
  int evaluations = 0;
  int failed = 0;
  std::vector<FailedEvaluation> failures;  // the first max_failures_kept failures
  double seconds = 0.0;                    // wall time, including runs before a resume
  SwarmSettings settings;                  // as run (from the checkpoint after a resume)

  // A finite best value exists.
  [[nodiscard]] bool usable() const;
  // One line: status, iterations, evaluations and failures, best value, time.
  [[nodiscard]] std::string brief_report() const;
};

// Throws an input Error for invalid settings or initial points (naming the field)
// and an Error when a checkpoint cannot be written. Failed evaluations never throw.
[[nodiscard]] SwarmSummary run_swarm(const ParameterSpace& space, const ParticleObjective& objective,
                                     const SwarmSettings& settings, const SwarmRunOptions& options = {});
[[nodiscard]] SwarmSummary run_swarm(const ParameterSpace& space, const Objective& objective,
                                     const SwarmSettings& settings, const SwarmRunOptions& options = {});

// Continues the run saved in `checkpoint` (settings come from the file). The space must be
// the one the run was started with. Throws an Error naming the file and the field
// when it cannot be read or does not match. A checkpoint of a finished run returns its
// summary without evaluating.
[[nodiscard]] SwarmSummary resume_swarm(const std::filesystem::path& checkpoint, const ParameterSpace& space,
                                        const ParticleObjective& objective, const SwarmRunOptions& options = {});
[[nodiscard]] SwarmSummary resume_swarm(const std::filesystem::path& checkpoint, const ParameterSpace& space,
                                        const Objective& objective, const SwarmRunOptions& options = {});

}  // namespace yarnfit::swarm
