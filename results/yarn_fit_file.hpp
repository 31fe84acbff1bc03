#pragma once
// yarn_fit.json (SPEC §5 `yarnfit yarn fit`) as a type: what the yarn stage wrote, read back by
// the reports, the summaries, batch and the CLI without knowing a JSON key. The yarn fit fills
// it (yarn::to_file, yarn_fit/fit/problem/yarn_fit_problem.hpp); to_json writes the file
// and yarn_fit_file_from_json reads it, of this version or an older one.
//
// Schema versions:
//   1  no `schema_version` key (every file before the results module);
//   2  `schema_version` 2; otherwise the same fields (the per-direction errors were already
//      stored by the fit).
//
// "No figure" (a failed evaluation, a check that did not run) is NaN here and null in the file.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "results/shell_fit_file.hpp"

namespace yarnfit::results {

inline constexpr int k_yarn_fit_schema_version = 2;
inline constexpr double k_nan_error = std::numeric_limits<double>::quiet_NaN();

// The yarn metric over all directions [%] (mean absolute error over the largest comfort-range
// target); NaN: no figure.
struct YarnErrors {
  double stress_comfort_pct = 0.0;
  double stress_full_pct = 0.0;
  double compression_pct = 0.0;
  double bending_pct = 0.0;  // checked after the fit, not fitted; NaN when the check did not run
};

// One direction's figures of the final evaluation.
struct YarnDirectionErrors {
  double stress_comfort_pct = 0.0;
  double stress_full_pct = 0.0;
  double compression_pct = 0.0;
  double comfort_stretch = 0.0;  // end of the comfort range
  double objective = 0.0;        // the direction's share of g
  long long samples = 0;
  int flat_compressions = 0;  // samples whose Ψ(c) was flat
  int held_compressions = 0;  // samples without a stable c
  std::optional<double> bending_pct;          // from the bending check, when it ran
  std::optional<double> curl_stress_kappa_N;  // the same check's curl stress

  // A direction without figures: every one NaN.
  [[nodiscard]] static YarnDirectionErrors none();
};

// One direction's uniform targets and the fitted model's values there (yarn_curves.csv).
struct YarnCurve {
  std::string direction;
  std::vector<double> stretch;
  std::vector<double> target_S_N_per_m;
  std::vector<double> simulated_S_N_per_m;
  std::vector<double> target_compression;
  std::vector<double> simulated_compression;
  std::vector<double> weight;
};

struct CheckOutcome {
  bool ok = false;
  std::string message;
};

struct YarnTiming {
  double swarm = 0.0;  // the global search, whichever method
  double local = 0.0;
  double bending_check = 0.0;
  double profile = 0.0;
  double total = 0.0;
};

// One parameter of the identifiability profile.
struct ProfileEntry {
  double value = 0.0;
  double objective_lower = 0.0;  // g at value ÷ (1 + step); NaN: that side failed
  double objective_upper = 0.0;
  double range_factor = 0.0;        // others re-fitted; NaN when unbounded (free)
  double range_alone_factor = 0.0;  // others held
  bool free = false;
  bool free_alone = false;
};

// How far the targets pin each fitted value (yarn_fit.json's `identifiability`).
struct Identifiability {
  bool computed = false;
  std::string from;  // "jacobian" or "evaluations"
  std::string message;
  double step = 0.0;
  double objective = 0.0;  // g at the fit
  std::map<std::string, ProfileEntry> parameters;
  int evaluations = 0;
  double seconds = 0.0;
};

struct SwarmStageSettings {
  int particles = 0;
  int iterations = 0;
  int samples = 0;
};

// The settings the fit ran with (after --resume: the checkpoint's particles and iterations).
struct YarnFitSettingsRecord {
  std::string global_method;
  SwarmStageSettings staged_contact;
  SwarmStageSettings staged_all;
  double staged_r1_window = 0.0;
  int staged_rescored = 0;
  int staged_starts = 0;
  int alternation_max_rounds = 0;
  int alternation_iterations_per_round = 0;
  double alternation_initial_radius = 0.0;
  double alternation_move_tolerance = 0.0;
  double alternation_rest_difference_step = 0.0;  // absent in older files: NaN
  int particles = 0;  // 0 without a global search
  int iterations = 0;
  int swarm_samples = 0;
  int local_samples = 0;
  std::string local_method;
  int local_evaluations = 0;
  int swarm_compression_nodes = 0;
  int local_compression_nodes = 0;
  std::uint64_t seed = 0;
  bool swarm = true;
  bool linear_stretch = false;
  bool rest_shape = true;
  bool rest_period = false;
  bool band_correction = false;
  int bending_points = 0;
  double profile_step = 0.0;
  bool swarm_cutoff = true;
  std::optional<std::map<std::string, double>> start;  // --start without a global search
  std::string resumed_from;                             // the checkpoint, after --resume
};

struct SwarmIterationRecord {
  int iteration = 0;
  double best = 0.0;
  int failed = 0;
};

struct SwarmRecord {
  double best = 0.0;
  int evaluations = 0;
  int failed = 0;
  int stopped_at_cutoff = 0;
  std::vector<SwarmIterationRecord> history;
  std::string report;
};

struct GlobalStageRecord {
  std::string stage;
  int evaluations = 0;
  int stopped_at_cutoff = 0;
  double best = 0.0;
  double seconds = 0.0;
  std::string report;
};

struct GlobalRecord {
  std::string method;
  std::vector<GlobalStageRecord> stages;
};

// Implicit filtering's iterations.
struct FilteringIterationRecord {
  int evaluations = 0;
  double scale = 0.0;
  double best = 0.0;
  std::string move;
  int trials = 0;
};

// The Gauss–Newton alternation's rounds.
struct AlternationRoundRecord {
  int round = 0;
  double objective_start = 0.0;
  double objective_held = 0.0;
  double objective_trial = 0.0;
  bool accepted = false;
  double move = 0.0;
  int iterations = 0;
  int evaluations = 0;
  std::string termination;
  bool rest_derivative_measured = false;  // after the round (issue 49); absent in older files: false
};

// Why the alternation handed over to implicit filtering, and how that went.
struct LocalFallback {
  std::string reason;
  std::string report;
};

// One local step; which optional parts it has depends on its method.
struct LocalRunRecord {
  std::string method;
  std::string status;
  bool converged = false;
  double best = 0.0;
  double start = 0.0;
  int evaluations = 0;
  int failed = 0;
  double seconds = 0.0;
  std::string report;
  // implicit filtering
  std::optional<int> iterations;
  std::optional<double> final_scale;
  std::optional<std::vector<FilteringIterationRecord>> history;
  // Gauss–Newton
  std::optional<std::vector<AlternationRoundRecord>> rounds;
  std::optional<double> last_move;
  std::optional<bool> fell_back;
  std::optional<LocalFallback> fallback;  // when implicit filtering took over
};

struct LocalRecord {
  LocalRunRecord best;                // the run the fit kept
  std::vector<LocalRunRecord> runs;  // every run (one per start)
};

// The fitted yarn model against the record's measured curves (issue 48): its own uniform
// responses homogenised back to a shell law (how far the law is from them: its misfit), and the
// record's clamped-stretch and pear-loop scenes run with that law, in the shell fit's metric and
// names. yarn_fit.json: `errors_vs_measured` {<direction>: {stretch_force_pct, compression_pct,
// bending_pct}, all: {…}} and `homogenised_law` {ok, message, model, params, misfit_pct, curves,
// bending_curves, seconds}.
struct MeasuredCheckRecord {
  bool ok = false;
  std::string message;  // why there are no figures, or which scene failed
  ShellErrors all{k_nan_error, k_nan_error, k_nan_error};
  std::map<std::string, ShellDirectionErrors> by_direction;
  std::string law_model;
  std::map<std::string, double> law_params;
  double law_stress_misfit_pct = k_nan_error;  // the yarn metric, law against the model's samples
  double law_compression_misfit_pct = k_nan_error;
  double law_bending_misfit_pct = k_nan_error;
  std::vector<ShellDirectionCurves> curves;  // the record's stretch tests and the law there
  std::vector<BendingCurve> bending_curves;  // its pear-loop tests and the law there
  double seconds = 0.0;
};

// The tile's shape fitted with the yarn parameters (issue 48; yarn_fit/fit/problem/shape_search.hpp):
// yarn_fit.json's `shape`.
struct ShapeTrialRecord {
  double aspect = 0.0;
  bool held = true;        // the period held at the aspect (false: the generated tile's own)
  double objective = 0.0;  // NaN: the trial failed
  double r1_m = 0.0;       // the contact radius its tile was built with
  bool full_fit = false;
  double seconds = 0.0;
  std::string message;
};
struct ShapeRecord {
  double aspect = 0.0;  // course / wale spacing of the fitted tile's loops
  bool held = false;    // its period held at that aspect (false: the generated tile's own won)
  double prior = 0.0;
  double lower = 0.0, upper = 0.0;              // the search bounds
  double range_lower = 0.0, range_upper = 0.0;  // where g stays within twice the best (NaN: open)
  std::string prior_source;
  double wale_spacing_mm = 0.0, course_spacing_mm = 0.0;
  std::vector<ShapeTrialRecord> trials;
  double seconds = 0.0;
};

// The tile the model was fitted on as a knitter reads it (issue 48; pipeline/fitted_tile.hpp):
// yarn_fit.json's `tile`, the output folder's tile.pyp described.
struct FittedTileRecord {
  std::string source;  // file, generated, generated at the record's gauge, shape search
  double period_weft_mm = 0.0, period_warp_mm = 0.0;
  double yarn_radius_mm = 0.0;  // as the tile file writes it
  int wales = 0, courses = 0;   // in one period; 0: not a weft knit (fabrics_db/tile/knit_gauge.hpp)
  double wales_per_10cm = 0.0, courses_per_10cm = 0.0;  // NaN without a count
  // The record's knitting_gauge, when it states one.
  std::optional<double> record_wales_per_10cm, record_courses_per_10cm;
};

struct YarnFitFile {
  int schema_version = k_yarn_fit_schema_version;  // as read; to_json writes the current one
  std::string fabric;
  std::string family;
  std::string targets;  // the uniform targets file the fit read
  bool ok = false;
  std::string message;
  std::map<std::string, double> params;  // every yarn parameter, SI
  YarnErrors errors;
  std::map<std::string, YarnDirectionErrors> errors_by_direction;
  std::string errors_reason;  // why there are no errors; empty when there are
  std::vector<YarnCurve> curves;  // in direction order
  std::vector<std::string> effects;
  std::map<std::string, SearchBound> bounds;  // the fitted parameters' search ranges
  std::optional<CheckOutcome> bending_check;  // present when the check said something
  double objective = 0.0;  // NaN: no final evaluation
  std::vector<std::string> on_bound;
  int evaluations = 0;
  YarnTiming timing_s;
  std::optional<Identifiability> identifiability;
  YarnFitSettingsRecord settings;
  std::optional<SwarmRecord> swarm;  // with a global search
  std::optional<GlobalRecord> global;
  std::optional<LocalRecord> local;  // when a local step ran
  std::optional<MeasuredCheckRecord> measured;  // errors_vs_measured, when the check ran
  std::optional<ShapeRecord> shape;             // when the tile's shape was fitted
  std::optional<FittedTileRecord> tile;         // the tile fitted on (files from before issue 48 have none)
};

// yarn_fit.json of the current schema version.
[[nodiscard]] nlohmann::json to_json(const YarnFitFile& file);

// A yarn_fit.json of any version; a field of the wrong type throws an Error naming it
// ("yarn_fit.json: curves[0].stretch: expected …"), as does a file that is not an object or lacks
// `params`. `source` names the file in messages.
[[nodiscard]] YarnFitFile yarn_fit_file_from_json(const nlohmann::json& json,
                                                 const std::string& source = "yarn_fit.json");

// The file at `path`; throws an Error naming it when it cannot be read or parsed.
[[nodiscard]] YarnFitFile read_yarn_fit_file(const std::filesystem::path& path);

// `errors_by_direction` as the file holds it (for reports that show it as it is).
[[nodiscard]] nlohmann::json direction_errors_json(const std::map<std::string, YarnDirectionErrors>& errors);

// The figures of `errors` under their names in the file (stress_comfort_pct, …), for tables
// whose columns take those names (the batch ledger, the report's metrics).
[[nodiscard]] std::map<std::string, double> named_errors(const YarnErrors& errors);
// The timing under its names in the file (swarm, local, bending_check, profile, total).
[[nodiscard]] std::map<std::string, double> named_times(const YarnTiming& timing);

}  // namespace yarnfit::results
