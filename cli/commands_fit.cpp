// yarnfit yarn fit / yarnfit fit: the yarn-level calibration (thesis 6.5.3; SPEC §1 step 3–4,
// §5) on uniform targets, and the whole pipeline shell fit → uniform targets → yarn fit.
//
// Files. `yarn fit FABRIC --targets CSV --out DIR` writes DIR/yarn_fit.json (SPEC §5, from
// calibration::to_json), DIR/yarn_curves.csv (the targets and the fitted model's response at
// the local step's stretch samples, per direction) and DIR/yarn_summary.txt (errors per
// direction, parameters with their bounds, time per stage). `fit FABRIC --out DIR` runs the
// `shell fit` command's own code path into DIR (shell_fit.json, uniform_targets.csv), writes
// DIR/shell_curves.csv from shell_fit.json's measured and simulated curves, then the yarn fit
// on DIR/uniform_targets.csv (yarn_fit.json, yarn_curves.csv) and DIR/summary.txt for both.
//
// Overwriting. These commands never replace an existing output file without --force: every
// file they would write is checked before any work starts, and each one found is reported
// (exit 2). Invalid input (fabric without a pattern or a yarn stiffness, unreadable targets,
// bad settings) exits 2 with one `file: field: message` line per problem; a calibration whose
// every candidate failed exits 1 after writing what it has.
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "calibration/fit/yarn_calibration.hpp"
#include "calibration/targets/uniform_targets_reader.hpp"
#include "cli/commands.hpp"
#include "fabrics_db/records/fabric_reader.hpp"
#include "fabrics_db/text_util.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct YarnFitArgs {
  std::string fabric, targets, out, checkpoint, start;
  calibration::YarnFitSettings defaults;
  int particles = defaults.particles;
  int iterations = defaults.iterations;
  int samples = defaults.swarm_samples;
  int local_samples = defaults.local_samples;
  int local_evaluations = defaults.local_evaluations;
  std::string local_method = calibration::to_string(defaults.local_method);
  std::uint64_t seed = defaults.seed;
  int threads = 0;
  int compression_nodes = defaults.local_compression_nodes;
  bool no_swarm = false, linear_stretch = false, no_rest_shape = false, resume = false, no_profile = false;
  bool quiet = false, force = false;
  // `fit` only: the shell stage.
  double mesh_mm = 5.0;
};

// The fabric's tile (weft along x) and the scales of the yarn parameters.
struct YarnInputs {
  db::Fabric fabric;
  yarn::YarnTile tile;
  yarn::ParameterScales scales;
  std::optional<yarn::YarnParams> start;  // --start
};

// --start FILE: the parameters the local step starts from, their optimised values inside
// the search bounds (the fixed ks2, kc2, R2 always come from the fabric).
void load_start(const YarnFitArgs& a, YarnInputs& in, std::vector<std::string>& problems) {
  if (a.start.empty()) return;
  db::Problems found;
  in.start = yarn::read_yarn_params(a.start, in.scales, found);
  for (const auto& p : found.items()) problems.push_back(p.to_string());
  if (!in.start) return;
  const auto space = calibration::yarn_parameter_space(in.scales, a.linear_stretch);
  const Eigen::VectorXd x = calibration::point_from_params(*in.start, a.linear_stretch);
  for (const std::string& outside : space.bounds_problems(x)) problems.push_back(a.start + ": " + outside + " of this fabric");
}

// Loads FABRIC and checks that it can be yarn-fitted: every problem is one line in `problems`.
std::optional<YarnInputs> load_yarn_inputs(const std::string& folder, std::vector<std::string>& problems) {
  const auto load = db::load_fabric(folder);
  if (!load.ok()) {
    for (const auto& p : load.problems.items()) problems.push_back(p.to_string());
    return std::nullopt;
  }
  const db::Fabric& fabric = *load.fabric;
  const std::string yaml = (fabric.folder / db::k_fabric_file_name).string();
  const auto stiffness = fabric.stiffest_yarn_stiffness();
  if (!fabric.pattern)
    problems.push_back(yaml + ": pattern: missing; a yarn fit needs the periodic yarn tile (pattern: {file: tile.pyp, "
                              "weft_axis: x})");
  if (!stiffness)
    problems.push_back(yaml + ": yarns.stiffness_N: missing; a yarn fit needs the stiffest yarn's stretch stiffness "
                              "(sets ks2, SPEC §3)");
  if (!problems.empty()) return std::nullopt;
  YarnInputs in{fabric, {}, {*stiffness, fabric.pattern->facts.r_est}, std::nullopt};
  try {
    in.tile = yarn::make_yarn_tile(fabric.pattern->tile);
  } catch (const std::exception& e) {
    problems.push_back(fabric.pattern->file.string() + ": pattern: " + e.what());
    return std::nullopt;
  }
  // The objective pulls along the tile's x axis for weft: turn a tile whose weft runs along y.
  if (fabric.pattern->weft_axis == db::Axis::y) in.tile = yarn::rotated_tile(in.tile, -std::numbers::pi / 2.0);
  if (!(in.scales.r_est > 0.0))
    problems.push_back(fabric.pattern->file.string() + ": pattern: no contact radius R_est could be computed");
  if (!problems.empty()) return std::nullopt;
  return in;
}

// Every output file that exists is a problem unless --force; DIR must be a folder.
void check_outputs(const std::string& out, const std::vector<std::string>& files, bool force,
                   std::vector<std::string>& problems) {
  if (fs::exists(out) && !fs::is_directory(out)) {
    problems.push_back("--out: " + out + ": exists and is not a folder");
    return;
  }
  if (force) return;
  for (const auto& f : files) {
    const fs::path p = fs::path(out) / f;
    if (fs::exists(p)) problems.push_back(p.string() + ": exists (use --force to replace it)");
  }
}

calibration::YarnFitSettings settings_from(const YarnFitArgs& a) {
  calibration::YarnFitSettings s;
  s.particles = a.particles;
  s.iterations = a.iterations;
  s.swarm_samples = a.samples;
  s.local_samples = a.local_samples;
  s.local_evaluations = a.local_evaluations;
  s.local_method = calibration::local_method_from_string(a.local_method).value_or(s.local_method);
  s.seed = a.seed;
  s.threads = a.threads;
  s.swarm = !a.no_swarm;
  s.linear_stretch = a.linear_stretch;
  s.rest_shape = !a.no_rest_shape;
  if (a.no_profile) s.profile_step = 0.0;
  s.swarm_compression_nodes = a.compression_nodes;
  s.local_compression_nodes = a.compression_nodes;
  s.checkpoint = a.checkpoint;
  s.resume = a.resume;
  return s;
}

// Progress on the terminal: one line rewritten in place. The estimate of the time left is
// for the current stage, from its mean time per step so far (the local step may stop before
// its evaluation budget, so there it is an upper bound).
class ProgressLine {
 public:
  explicit ProgressLine(std::string prefix) : m_prefix(std::move(prefix)) {}
  void operator()(const std::string& stage, int step, int steps, double best, double seconds) {
    const std::lock_guard lock(m_mutex);
    if (stage != m_stage) {  // the stage began when the previous one last reported
      m_stage = stage;
      m_stage_start = m_last_seconds;
      m_first_step = step;
    }
    m_last_seconds = seconds;
    char best_text[32] = "-";
    if (std::isfinite(best)) std::snprintf(best_text, sizeof best_text, "%.4g", best);
    std::string left;
    const int done = step - m_first_step + 1;
    if (steps > 0 && step < steps && done > 0 && seconds > m_stage_start) {
      const double per_step = (seconds - m_stage_start) / done;
      left = ", about " + db::format_g(std::ceil(per_step * (steps - step)), 4) + " s left in this stage" +
             (stage == "local" ? " (at most)" : "");
    }
    std::fprintf(stderr, "\r\033[K%s: %s %d/%d, best objective %s, %.1f s%s", m_prefix.c_str(), stage.c_str(), step,
                 steps, best_text, seconds, left.c_str());
    std::fflush(stderr);
    m_shown = true;
  }
  void finish() {
    const std::lock_guard lock(m_mutex);
    if (m_shown) std::fprintf(stderr, "\n");
    m_shown = false;
  }

 private:
  std::mutex m_mutex;
  std::string m_prefix;
  std::string m_stage;
  double m_stage_start = 0.0;
  double m_last_seconds = 0.0;
  int m_first_step = 0;
  bool m_shown = false;
};

std::string pct(double v) { return std::isfinite(v) ? db::format_g(v, 3) + " %" : std::string("-"); }

// yarn_curves.csv: per direction and stretch sample, target and simulated second
// Piola-Kirchhoff stress S = σ_s/(1+s) [N/m] and zero-orthogonal-stress compression c.
std::string yarn_curves_csv(const calibration::ObjectiveResult& final) {
  std::ostringstream csv;
  csv << std::setprecision(10);
  csv << "direction,sample,stretch,target_S_N_per_m,simulated_S_N_per_m,target_compression,simulated_compression,"
         "weight\n";
  for (const auto& d : final.directions) {
    for (std::size_t i = 0; i < d.stretch.size(); ++i) {
      auto at = [i](const std::vector<double>& v) { return i < v.size() ? v[i] : std::nan(""); };
      csv << db::to_string(d.scale.direction) << "," << i << "," << d.stretch[i] << "," << at(d.stress_target) << ","
          << at(d.stress_sim) << "," << at(d.compression_target) << "," << at(d.compression_sim) << ","
          << at(d.weight) << "\n";
    }
  }
  return csv.str();
}

// A range factor f as the user reads it: "±4.2 %" when small, "÷/× 3.1" when not.
std::string range(double f) {
  if (std::isnan(f)) return "-";
  if (std::isinf(f)) return "unbounded";
  if (f > 100.0) return "÷/× > 100";
  return f < 1.5 ? "±" + db::format_g(100.0 * (f - 1.0), 2) + " %" : "÷/× " + db::format_g(f, 2);
}

// Which fitted values the targets stand behind (parameter_profile.hpp).
std::string profile_summary(const calibration::ParameterProfile& p) {
  if (p.step == 0.0) return {};
  std::ostringstream out;
  if (!p.computed) {
    out << "  identifiability: not computed (" << p.message << ")\n";
    return out.str();
  }
  const std::string f = db::format_g(1.0 + p.step, 3);
  out << "  identifiability (g = " << db::format_g(p.g_fit, 3)
      << " at the fit; range: how far a parameter moves before g doubles):\n"
      << "    parameter  g at ÷" << f << " / ×" << f << "    range, others re-fitted   others held\n";
  std::string downhill;
  for (const auto& e : p.entries) {
    const std::string g = db::format_g(e.g_lower, 3) + " / " + db::format_g(e.g_upper, 3);
    out << "    " << std::left << std::setw(9) << e.name << "  " << std::setw(22) << g << std::right << std::setw(19)
        << range(e.range_factor) << std::setw(16) << range(e.range_alone_factor) << "\n";
    if (std::min(e.g_lower, e.g_upper) < 0.99 * p.g_fit) downhill += (downhill.empty() ? "" : ", ") + e.name;
  }
  out << "    a range wider than the accuracy you need: the targets do not pin that parameter, and its value is one "
         "of many that fit as well\n";
  // The ranges assume the fit is a minimum; where a 10 % step lowers g it is not.
  if (!downhill.empty())
    out << "    g falls by more than 1 % with " << downhill
        << " moved: the fit is not at a minimum there (ranges are rough; more --local-evaluations may help)\n";
  if (!p.message.empty()) out << "    incomplete: " << p.message << "\n";
  return out.str();
}

// The human-readable part on the yarn fit: errors per direction, parameters with bounds and
// on-bound flags, time per stage.
std::string yarn_summary(const calibration::YarnFitResult& r, const calibration::YarnFitSettings& s,
                         const yarn::ParameterScales& scales) {
  std::ostringstream out;
  out << "yarn fit: " << (r.ok ? "ok" : "FAILED: " + r.message) << "\n";
  // After --resume the swarm ran with the checkpoint's settings, not the command line's.
  const bool resumed = s.swarm && s.resume && !r.swarm.history.empty();
  const int particles = resumed ? r.swarm.settings.particles : s.particles;
  const int iterations = resumed ? r.swarm.settings.iterations : s.iterations;
  out << "  settings: " << (s.swarm ? std::to_string(particles) + " particles x " + std::to_string(iterations) +
                                          " iterations, " + std::to_string(s.swarm_samples) + " samples per direction; "
                                    : std::string(s.start ? "no swarm, started from --start; " : "no swarm; "))
      << "local step " << calibration::to_string(s.local_method) << ", at most " << s.local_evaluations
      << " evaluations, " << s.local_samples << " samples per direction; seed "
      << s.seed << (s.linear_stretch ? "; linear stretch (ks1 = ks2, eps_s = 0)" : "")
      << (s.rest_shape ? "" : "; no rest-shape heuristic")
      << (s.local_compression_nodes == 0
              ? std::string("; c* at every sample")
              : "; c* at " + std::to_string(s.local_compression_nodes) + " samples, linear between")
      << "\n";
  out << "  errors (mean abs. error / largest comfort-range target):\n";
  out << "    direction  stress comfort  stress full  compression  bending (checked, not fitted)\n";
  for (const auto& d : r.final.directions) {
    double bending = std::nan("");
    for (const auto& b : r.bending.directions)
      if (r.bending.ok && b.direction == d.scale.direction) bending = b.error_pct;
    out << "    " << std::left << std::setw(9) << db::to_string(d.scale.direction) << std::right << "  " << std::setw(14)
        << pct(d.stress_comfort_pct) << "  " << std::setw(11) << pct(d.stress_full_pct) << "  " << std::setw(11)
        << pct(d.compression_pct) << "  " << std::setw(8) << pct(bending) << "\n";
  }
  if (!r.bending.ok && !r.bending.message.empty()) out << "  bending check failed: " << r.bending.message << "\n";
  const json j = yarn::to_json(r.params);
  out << "  parameters (SI):\n";
  const auto space = calibration::yarn_parameter_space(scales, s.linear_stretch);
  for (const auto& p : space.parameters()) {
    const bool on = std::find(r.on_bound.begin(), r.on_bound.end(), p.name) != r.on_bound.end();
    const double v = j.contains(p.name) ? j[p.name].get<double>() : std::nan("");
    out << "    " << std::left << std::setw(6) << p.name << std::right << " = " << std::setw(12) << db::format_g(v, 5)
        << "   in [" << db::format_g(p.lower, 4) << ", " << db::format_g(p.upper, 4) << "]"
        << (p.log_space ? " log" : "") << (on ? "   ON A BOUND" : "") << "\n";
  }
  for (const char* k : {"ks1", "eps_s", "ks2", "kc2", "R2"}) {
    bool optimised = false;
    for (const auto& p : space.parameters()) optimised = optimised || p.name == k;
    if (!optimised && j.contains(k)) out << "    " << std::left << std::setw(6) << k << std::right << " = " << std::setw(12)
                                         << db::format_g(j[k].get<double>(), 5) << "   fixed\n";
  }
  out << profile_summary(r.profile);
  out << "  evaluations: " << r.evaluations << "\n";
  out << "  time: swarm " << db::format_g(r.seconds_swarm, 3) << " s, local " << db::format_g(r.seconds_local, 3)
      << " s" << (r.profile.computed ? ", profile " + db::format_g(r.profile.seconds, 3) + " s" : std::string())
      << ", total " << db::format_g(r.seconds_total, 3) << " s\n";
  if (!r.swarm.history.empty())
    out << "  swarm: " << r.swarm.brief_report() << "; " << r.swarm_stopped
        << " candidates stopped once they could not beat their particle's best\n";
  if (r.local.ran) out << "  local: " << r.local.report << "\n";
  return out.str();
}

struct YarnStage {
  int exit_code = k_exit_ok;
  std::string summary;  // yarn_summary text (empty when nothing ran)
};

// Runs the calibration on `targets_file` and writes yarn_fit.json and yarn_curves.csv into
// a.out, and yarn_summary.txt when `summary_file` is not empty. Prints problems on stderr.
YarnStage run_yarn_stage(const YarnInputs& in, const YarnFitArgs& a,
                         const std::vector<calibration::DirectionTargets>& targets, const fs::path& targets_file,
                         const std::string& summary_file) {
  YarnStage stage;
  calibration::YarnFitSettings settings = settings_from(a);
  if (in.start) {
    settings.start = in.start;
    settings.swarm = false;
  }
  if (const auto why = settings.invalid_reason(); !why.empty()) {
    std::cerr << "yarn fit settings: " << why << "\n";
    stage.exit_code = k_exit_invalid_input;
    return stage;
  }
  const bool show_progress = !a.quiet && ::isatty(STDERR_FILENO);
  auto progress = std::make_shared<ProgressLine>("yarn fit " + in.fabric.id);
  if (show_progress) settings.progress = [progress](const std::string& st, int step, int steps, double best, double t) {
    (*progress)(st, step, steps, best, t);
  };
  if (a.threads > 0) omp_set_num_threads(a.threads);

  calibration::YarnFitResult result;
  try {
    result = calibration::fit_yarn_params(in.tile, targets, in.scales, settings);
  } catch (const std::invalid_argument& e) {
    progress->finish();
    std::cerr << targets_file.string() << ": " << e.what() << "\n";
    stage.exit_code = k_exit_invalid_input;
    return stage;
  }
  progress->finish();

  json report = calibration::to_json(result, settings);
  if (settings.swarm && settings.resume && !result.swarm.history.empty() && report.contains("settings")) {
    report["settings"]["particles"] = result.swarm.settings.particles;  // the checkpoint's
    report["settings"]["iterations"] = result.swarm.settings.iterations;
    report["settings"]["resumed_from"] = settings.checkpoint.string();
  }
  if (!report.contains("fabric")) report["fabric"] = in.fabric.id;
  if (!report.contains("targets")) report["targets"] = targets_file.string();
  stage.summary = yarn_summary(result, settings, in.scales);
  try {
    fs::create_directories(a.out);
    db::write_text_file_atomically(fs::path(a.out) / "yarn_fit.json", report.dump(2) + "\n");
    db::write_text_file_atomically(fs::path(a.out) / "yarn_curves.csv", yarn_curves_csv(result.final));
    if (!summary_file.empty())
      db::write_text_file_atomically(fs::path(a.out) / summary_file,
                                     "fabric " + in.fabric.id + ", targets " + targets_file.string() + "\n" +
                                         stage.summary);
  } catch (const std::exception& e) {
    std::cerr << a.out << ": file: " << e.what() << "\n";
    stage.exit_code = k_exit_internal;
    return stage;
  }
  if (!result.ok) {
    std::cerr << "yarn fit failed: " << result.message << "\n";
    stage.exit_code = k_exit_internal;
  }
  return stage;
}

const std::vector<std::string> k_yarn_outputs{"yarn_fit.json", "yarn_curves.csv", "yarn_summary.txt"};

int run_yarn_fit(const YarnFitArgs& a) {
  std::vector<std::string> problems;
  auto in = load_yarn_inputs(a.fabric, problems);
  if (in) load_start(a, *in, problems);
  db::Problems found;
  const auto targets = calibration::read_uniform_targets(a.targets, found);
  for (const auto& p : found.items()) problems.push_back(p.to_string());
  if (!a.resume) check_outputs(a.out, k_yarn_outputs, a.force, problems);
  if (!problems.empty() || !in || !targets) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  const auto stage = run_yarn_stage(*in, a, *targets, a.targets, "yarn_summary.txt");
  if (!a.quiet && !stage.summary.empty()) {
    std::cout << "yarn fit of " << in->fabric.id << "\n" << stage.summary;
    std::cout << "results in " << a.out << ": yarn_fit.json, yarn_curves.csv, yarn_summary.txt\n";
  }
  return stage.exit_code;
}

// ---------------------------------------------------------------------------- fit (pipeline)

// Shell errors per direction from shell_fit.json's curves: mean |sim − meas| / mean |meas|
// in percent (SPEC §3, Fig. 6.13); NaN when a curve is missing.
double curve_error_pct(const json& d, const char* measured, const char* simulated) {
  if (!d.contains(measured) || !d.contains(simulated)) return std::nan("");
  const auto& m = d[measured];
  const auto& s = d[simulated];
  if (!m.is_array() || !s.is_array() || m.empty() || m.size() != s.size()) return std::nan("");
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!m[i].is_number() || !s[i].is_number()) return std::nan("");
    num += std::abs(s[i].get<double>() - m[i].get<double>());
    den += std::abs(m[i].get<double>());
  }
  return den > 0.0 ? 100.0 * num / den : std::nan("");
}

std::string shell_curves_csv(const json& report) {
  std::ostringstream csv;
  csv << std::setprecision(10) << "direction,stretch,measured_force_N,simulated_force_N,measured_compression,"
                                  "simulated_compression\n";
  if (!report.contains("directions")) return csv.str();
  for (const auto& d : report["directions"]) {
    const auto& st = d["stretch"];
    auto cell = [&d](const char* key, std::size_t i) -> std::string {
      if (!d.contains(key) || !d[key].is_array() || i >= d[key].size() || !d[key][i].is_number()) return "";
      std::ostringstream v;
      v << std::setprecision(10) << d[key][i].get<double>();
      return v.str();
    };
    for (std::size_t i = 0; i < st.size(); ++i)
      csv << d["direction"].get<std::string>() << "," << st[i].get<double>() << "," << cell("measured_force_N", i)
          << "," << cell("simulated_force_N", i) << "," << cell("measured_compression", i) << ","
          << cell("simulated_compression", i) << "\n";
  }
  return csv.str();
}

std::string number_text(const json& v, int digits = 4) {
  return v.is_number() ? db::format_g(v.get<double>(), digits) : std::string("-");
}

std::string shell_summary(const json& report, double wall_seconds) {
  std::ostringstream out;
  out << "shell fit: " << (report.value("converged", false) ? "converged" : "NOT converged") << "\n";
  out << "  errors (mean abs. error / mean abs. measured value):\n";
  out << "    direction  force        compression\n";
  if (report.contains("directions")) {
    for (const auto& d : report["directions"])
      out << "    " << std::left << std::setw(9) << d["direction"].get<std::string>() << std::right << "  "
          << std::setw(11) << pct(curve_error_pct(d, "measured_force_N", "simulated_force_N")) << "  "
          << std::setw(11) << pct(curve_error_pct(d, "measured_compression", "simulated_compression")) << "\n";
  }
  const json& e = report["errors"];
  out << "    all        " << std::setw(11) << pct(e["stretch_force_pct"].is_number() ? e["stretch_force_pct"].get<double>() : std::nan(""))
      << "  " << std::setw(11) << pct(e["compression_pct"].is_number() ? e["compression_pct"].get<double>() : std::nan(""))
      << "   bending (aspect ratio) "
      << (e.contains("bending_pct") && e["bending_pct"].is_number() ? pct(e["bending_pct"].get<double>())
                                                                 : std::string("not fitted"))
      << "\n";
  out << "  parameters (N/m; k_theta in N*m):";
  std::vector<std::string> not_fitted;
  for (const auto& [k, v] : report["params"].items()) {
    if (v.is_number()) out << " " << k << " = " << number_text(v);
    else not_fitted.push_back(k);
  }
  if (!not_fitted.empty()) out << "; not fitted: " << db::join_words(not_fitted, " and ");
  out << "\n  time: " << db::format_g(wall_seconds, 3) << " s (fits " << number_text(report.value("timing_s", json()), 3)
      << " s, the rest reading the record and writing the uniform targets)\n";
  return out.str();
}

const std::vector<std::string> k_fit_outputs{"shell_fit.json", "uniform_targets.csv", "shell_curves.csv",
                                             "yarn_fit.json",  "yarn_curves.csv",     "summary.txt"};

int run_fit(const YarnFitArgs& a) {
  const auto start = Clock::now();
  std::vector<std::string> problems;
  auto in = load_yarn_inputs(a.fabric, problems);
  if (in) load_start(a, *in, problems);
  check_outputs(a.out, k_fit_outputs, a.force, problems);
  if (!problems.empty() || !in) {
    for (const auto& p : problems) std::cerr << p << "\n";
    return k_exit_invalid_input;
  }
  // Stage 1: exactly what `shell fit FABRIC --out DIR` does.
  const int shell_code = run_shell_fit_command(a.fabric, a.out, a.mesh_mm, a.threads > 0 ? a.threads : 2, a.quiet);
  const double shell_wall = seconds_since(start);
  if (shell_code != k_exit_ok) {
    std::cerr << "fit: the shell stage failed (exit " << shell_code << "); no yarn fit\n";
    return shell_code;
  }
  const fs::path out(a.out);
  std::string text, why;
  json shell_report;
  if (db::read_text_file(out / "shell_fit.json", text, why)) shell_report = json::parse(text, nullptr, false);
  if (shell_report.is_discarded() || !shell_report.is_object()) {
    std::cerr << (out / "shell_fit.json").string() << ": cannot read back the shell fit: " << why << "\n";
    return k_exit_internal;
  }
  const std::string shell_text = shell_summary(shell_report, shell_wall);
  try {
    db::write_text_file_atomically(out / "shell_curves.csv", shell_curves_csv(shell_report));
  } catch (const std::exception& e) {
    std::cerr << a.out << ": file: " << e.what() << "\n";
    return k_exit_internal;
  }

  // Stage 2: the yarn fit on the shell's uniform targets.
  const auto yarn_start = Clock::now();
  db::Problems found;
  const auto targets = calibration::read_uniform_targets(out / "uniform_targets.csv", found);
  if (!targets) {
    for (const auto& p : found.items()) std::cerr << p.to_string() << "\n";
    return k_exit_internal;  // written by the shell stage: not the user's input
  }
  const auto stage = run_yarn_stage(*in, a, *targets, out / "uniform_targets.csv", "");
  const double yarn_wall = seconds_since(yarn_start);
  if (stage.summary.empty()) return stage.exit_code;
  std::ostringstream summary;
  summary << "fabric " << in->fabric.id << " (" << a.fabric << ")\n\n"
          << shell_text << "\n"
          << stage.summary << "\n"
          << "time per stage: shell " << db::format_g(shell_wall, 3) << " s, yarn " << db::format_g(yarn_wall, 3)
          << " s, total " << db::format_g(seconds_since(start), 3) << " s\n";
  try {
    db::write_text_file_atomically(out / "summary.txt", summary.str());
  } catch (const std::exception& e) {
    std::cerr << a.out << ": file: " << e.what() << "\n";
    return k_exit_internal;
  }
  if (!a.quiet) {
    std::cout << "\n" << summary.str();
    std::cout << "results in " << a.out
              << ": summary.txt, shell_fit.json, uniform_targets.csv, shell_curves.csv, yarn_fit.json, "
                 "yarn_curves.csv\n";
  }
  return stage.exit_code;
}

// Options shared by `yarn fit` and `fit`.
void add_yarn_fit_options(CLI::App& cmd, YarnFitArgs& a) {
  cmd.add_option("FABRIC", a.fabric, "Fabric folder (needs pattern and a yarn stiffness_N)")->required();
  cmd.add_option("-o,--out", a.out, "Output folder")->required();
  cmd.add_option("--particles", a.particles, "Swarm particles")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd.add_option("--iterations", a.iterations, "Swarm iterations")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd.add_option("--samples", a.samples, "Stretch samples per direction in the swarm")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  cmd.add_option("--local-samples", a.local_samples, "Stretch samples per direction in the local step")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  cmd.add_option("--local-evaluations", a.local_evaluations, "The local step's budget of objective evaluations")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd.add_option("--local-method", a.local_method,
                 "Local step: implicit-filtering (Gauss-Newton steps on stencil differences whose scale shrinks "
                 "from 2 % to 0.5 % of every range; robust to the objective's small-scale roughness) or cobyla "
                 "(the thesis's choice)")
      ->check(CLI::IsMember({"implicit-filtering", "cobyla"}))
      ->capture_default_str();
  cmd.add_option("--seed", a.seed, "Swarm seed (same seed, same result whatever --threads)")->capture_default_str();
  cmd.add_option("--threads", a.threads, "OpenMP threads evaluating particles (0: OpenMP's default)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd.add_option("--compression-nodes", a.compression_nodes,
                 "Where the zero-orthogonal-stress compression is solved: 0 at every stretch sample; N >= 2 at N "
                 "samples with linear interpolation between them (2: the thesis's both ends)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd.add_option("--start", a.start,
                 "Skip the swarm and start the local step from these parameters (Y.yaml with yarn_fit.json's params "
                 "keys, or a yarn_fit.json): to refine an earlier fit");
  cmd.add_flag("--no-swarm", a.no_swarm, "The local step alone from the middle of the bounds (ablation, Fig. 6.11)");
  cmd.add_flag("--linear-stretch", a.linear_stretch, "ks1 = ks2, eps_s = 0: no biphasic stretch (ablation, Fig. 6.16)");
  cmd.add_flag("--no-rest-shape", a.no_rest_shape, "Keep the tile's own rest shape (ablation, Fig. 6.17)");
  cmd.add_flag("--no-profile", a.no_profile,
               "Skip the identifiability profile (each fitted parameter moved 10 % both ways, 2 local-step "
               "evaluations per parameter)");
  cmd.add_flag("-q,--quiet", a.quiet, "No progress or summary on the terminal");
  cmd.add_flag("--force", a.force, "Replace existing output files in the folder");
}

}  // namespace

void add_fit_commands(CLI::App& app, CLI::App& yarn, int& exit_code) {
  auto yargs = std::make_shared<YarnFitArgs>();
  auto* y = yarn.add_subcommand(
      "fit", "Fit the yarn parameters {ks1, eps_s, kb, R1, kc1} to uniform targets (swarm, then a local step by "
             "implicit filtering or COBYLA; rest-shape heuristic per candidate); writes DIR/yarn_fit.json, "
             "yarn_curves.csv and yarn_summary.txt");
  add_yarn_fit_options(*y, *yargs);
  y->add_option("--targets", yargs->targets, "uniform_targets.csv (as `shell fit` or `synth yarn` write it)")
      ->required();
  auto* checkpoint = y->add_option("--checkpoint", yargs->checkpoint, "Swarm checkpoint file, written every iteration");
  y->add_flag("--resume", yargs->resume, "Continue the swarm from --checkpoint with its particles and iterations (give the same --samples); "
              "output files may exist")
      ->needs(checkpoint);
  y->callback([yargs, &exit_code] { exit_code = run_yarn_fit(*yargs); });

  auto fargs = std::make_shared<YarnFitArgs>();
  auto* f = app.add_subcommand(
      "fit", "The whole pipeline: shell fit (shell_fit.json, uniform_targets.csv, shell_curves.csv), then the yarn "
             "fit on its targets (yarn_fit.json, yarn_curves.csv), and DIR/summary.txt for both");
  add_yarn_fit_options(*f, *fargs);
  f->add_option("--mesh", fargs->mesh_mm, "Shell stage: mesh cell size [mm]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  f->callback([fargs, &exit_code] { exit_code = run_fit(*fargs); });
}

}  // namespace yarnfit::cli
