#include "reports/summaries/yarn_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "fabrics_db/text_util.hpp"
#include "results/metrics/error_metrics.hpp"
#include "reports/summaries/text.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::reports {

namespace {

using numerics::k_inf;
using numerics::k_nan;

// The optimised parameters in the order of the fit's parameter space (SPEC §3: p = {ks1, ε̄s,
// kb, R1, kc1}); JSON objects sort their keys, the tables keep this order.
const char* const k_fitted[] = {"ks1", "eps_s", "kb", "R1", "kc1"};

// A range factor as the file holds it: NaN (null) means unbounded when the entry says "free".
double factor(double f, bool free) { return std::isnan(f) && free ? k_inf : f; }

// A range factor f as the user reads it: "±4.2 %" when small, "÷/× 3.1" when not.
std::string range(double f) {
  if (std::isnan(f)) return "-";
  if (std::isinf(f)) return "unbounded";
  if (f > 100.0) return "÷/× > 100";
  return f < 1.5 ? "±" + db::format_g(100.0 * (f - 1.0), 2) + " %" : "÷/× " + db::format_g(f, 2);
}

// Which fitted values the targets stand behind (yarn_fit.json's `identifiability`).
std::string profile_summary(const results::Identifiability& p) {
  if (!std::isfinite(p.step) || p.step == 0.0) return {};  // the profile was not asked for
  std::ostringstream out;
  if (!p.computed) {
    out << "  identifiability: not computed (" << p.message << ")\n";
    return out.str();
  }
  const std::string f = db::format_g(1.0 + p.step, 3);
  // From the Gauss–Newton step's exact Jacobian at the fit, the one-at-a-time g values are its
  // model's; from evaluations (the other local steps), they were simulated.
  const bool model = p.from == "jacobian";
  out << "  identifiability (g = " << db::format_g(p.objective, 3)
      << " at the fit; range: how far a parameter moves before g doubles; "
      << (model ? "from the exact Jacobian at the fit" : "from simulations at ÷/× " + f) << "):\n"
      << "    parameter  g at ÷" << f << " / ×" << f << (model ? " (model)" : "") << "    range, others re-fitted   others held\n";
  std::string downhill;
  for (const char* name : k_fitted) {
    const auto it = p.parameters.find(name);
    if (it == p.parameters.end()) continue;
    const results::ProfileEntry& e = it->second;
    // A side that failed has no figure: its g was +inf.
    const double g_lower = std::isnan(e.objective_lower) ? k_inf : e.objective_lower;
    const double g_upper = std::isnan(e.objective_upper) ? k_inf : e.objective_upper;
    const std::string g = db::format_g(g_lower, 3) + " / " + db::format_g(g_upper, 3);
    out << "    " << std::left << std::setw(9) << name << "  " << std::setw(22) << g << std::right << std::setw(19)
        << range(factor(e.range_factor, e.free)) << std::setw(16) << range(factor(e.range_alone_factor, e.free_alone))
        << "\n";
    if (std::min(g_lower, g_upper) < 0.99 * p.objective) downhill += (downhill.empty() ? "" : ", ") + std::string(name);
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

std::string settings_line(const results::YarnFitSettingsRecord& s) {
  std::ostringstream out;
  const int nodes = s.local_compression_nodes;
  const auto stage = [](const results::SwarmStageSettings& st) {
    return std::to_string(st.particles) + " x " + std::to_string(st.iterations) + " on " + std::to_string(st.samples) +
           " samples";
  };
  std::string global;
  if (!s.swarm) global = s.start ? "no global search, started from --start; " : "no global search; ";
  else if (s.global_method == "staged")
    global = "staged search (contact " + stage(s.staged_contact) + ", all " + stage(s.staged_all) + ", " +
             std::to_string(s.staged_starts) + " local starts); ";
  else
    global = "swarm " + std::to_string(s.particles) + " particles x " + std::to_string(s.iterations) + " iterations, " +
             std::to_string(s.swarm_samples) + " samples per direction; ";
  const std::string& method = s.local_method;
  out << "  settings: " << global << "local step " << method
      << (method == "gauss-newton" ? " (at most " + std::to_string(s.alternation_max_rounds) + " rounds)"
                                   : ", at most " + std::to_string(s.local_evaluations) + " evaluations")
      << ", " << s.local_samples << " samples per direction; seed " << s.seed
      << (s.linear_stretch ? "; linear stretch (ks1 = ks2, eps_s = 0)" : "")
      << (s.rest_shape ? "" : "; no rest-shape heuristic") << (s.rest_period ? "; period relaxed per candidate" : "")
      << (nodes == 0 ? std::string("; c* at every sample") : "; c* at " + std::to_string(nodes) + " samples, linear between")
      << "\n";
  return out.str();
}

// The errors table, one row per direction of the final curves.
std::string errors_table(const results::YarnFitFile& r) {
  std::ostringstream out;
  out << "  errors (mean abs. error / largest comfort-range target):\n";
  out << "    direction  stress comfort  stress full  compression  bending\n";
  for (const auto& c : r.curves) {
    const auto it = r.errors_by_direction.find(c.direction);
    const results::YarnDirectionErrors e =
        it != r.errors_by_direction.end() ? it->second : results::YarnDirectionErrors::none();
    out << "    " << std::left << std::setw(9) << c.direction << std::right << "  " << std::setw(14)
        << pct(e.stress_comfort_pct) << "  " << std::setw(11) << pct(e.stress_full_pct) << "  " << std::setw(11)
        << pct(e.compression_pct) << "  " << std::setw(8) << pct(e.bending_pct.value_or(k_nan)) << "\n";
  }
  if (!r.errors_reason.empty()) out << "  no errors: " << r.errors_reason << "\n";
  if (r.bending_check && !r.bending_check->ok && !r.bending_check->message.empty())
    out << "  bending check failed: " << r.bending_check->message << "\n";
  return out.str();
}

// The fitted model against the record's measured curves (yarn_fit.json errors_vs_measured),
// the shape the tile was fitted with, and the tile as a knitter reads it.
std::string measured_and_shape(const results::YarnFitFile& r) {
  std::ostringstream out;
  if (r.measured) {
    const results::MeasuredCheckRecord& m = *r.measured;
    out << "  against the measured curves (the model homogenised to a " << m.law_model << " law, misfit "
        << pct(m.law_stress_misfit_pct) << " stress, " << pct(m.law_compression_misfit_pct)
        << " compression; the shell fit's metric):\n";
    out << "    direction  force     compression  aspect ratio\n";
    for (const auto& [dir, e] : m.by_direction)
      out << "    " << std::left << std::setw(9) << dir << std::right << "  " << std::setw(8) << pct(e.stretch_force_pct)
          << "  " << std::setw(11) << pct(e.compression_pct) << "  " << std::setw(12) << pct(e.bending_pct) << "\n";
    out << "    " << std::left << std::setw(9) << "all" << std::right << "  " << std::setw(8) << pct(m.all.stretch_force_pct)
        << "  " << std::setw(11) << pct(m.all.compression_pct) << "  " << std::setw(12) << pct(m.all.bending_pct) << "\n";
    if (!m.message.empty()) out << "    (" << m.message << ")\n";
  }
  if (r.shape) {
    const results::ShapeRecord& s = *r.shape;
    out << "  tile shape: course/wale aspect " << std::setprecision(3) << s.aspect << " ("
        << (s.held ? "held" : "the generated tile's own period") << "; prior " << s.prior << ", " << s.trials.size()
        << " trials), wales " << 100.0 / s.wale_spacing_mm << " and courses " << 100.0 / s.course_spacing_mm
        << " per 10 cm\n";
  }
  if (r.tile) {
    const results::FittedTileRecord& t = *r.tile;
    out << "  tile: " << t.source << ", " << std::setprecision(4) << t.period_weft_mm << " x " << t.period_warp_mm << " mm";
    if (t.wales > 0)
      out << "; " << std::setprecision(3) << t.wales_per_10cm << " wales and " << t.courses_per_10cm << " courses per 10 cm";
    if (t.record_wales_per_10cm && t.record_courses_per_10cm)
      out << " (the record: " << *t.record_wales_per_10cm << " and " << *t.record_courses_per_10cm << ")";
    out << "\n";
  }
  return out.str();
}

// The fitted parameters on their bounds, then the fixed ones.
std::string parameters_table(const results::YarnFitFile& r) {
  std::ostringstream out;
  const auto param = [&r](const std::string& name) {
    const auto it = r.params.find(name);
    return it == r.params.end() ? k_nan : it->second;
  };
  out << "  parameters (SI):\n";
  for (const char* name : k_fitted) {
    const auto b = r.bounds.find(name);
    if (b == r.bounds.end()) continue;
    const bool on = std::find(r.on_bound.begin(), r.on_bound.end(), name) != r.on_bound.end();
    out << "    " << std::left << std::setw(6) << name << std::right << " = " << std::setw(12)
        << db::format_g(param(name), 5) << "   in [" << db::format_g(b->second.lower, 4) << ", "
        << db::format_g(b->second.upper, 4) << "]" << (b->second.log ? " log" : "") << (on ? "   ON A BOUND" : "")
        << "\n";
  }
  for (const char* k : {"ks1", "eps_s", "ks2", "kc2", "R2"})
    if (!r.bounds.count(k) && r.params.count(k))
      out << "    " << std::left << std::setw(6) << k << std::right << " = " << std::setw(12) << db::format_g(param(k), 5)
          << "   fixed\n";
  return out.str();
}

// Time per stage and the global and local searches' one-line reports.
std::string search_lines(const results::YarnFitFile& r) {
  std::ostringstream out;
  const results::YarnTiming& t = r.timing_s;
  const bool profiled = r.identifiability && r.identifiability->computed;
  out << "  time: global " << number_text(t.swarm, 3) << " s, local " << number_text(t.local, 3) << " s"
      << (profiled ? ", profile " + number_text(t.profile, 3) + " s" : std::string()) << ", total "
      << number_text(t.total, 3) << " s\n";
  if (r.global && !r.global->stages.empty()) {
    for (const auto& st : r.global->stages)
      out << "  " << st.stage << ": "
          << (st.report.empty() ? std::to_string(st.evaluations) + " evaluations" : st.report) << ", best g "
          << number_text(st.best, 4)
          << (st.stopped_at_cutoff > 0 ? "; " + std::to_string(st.stopped_at_cutoff) +
                                             " candidates stopped once they could not beat their particle's best"
                                       : std::string())
          << "\n";
  } else if (r.swarm && !r.swarm->history.empty()) {
    out << "  swarm: " << r.swarm->report << "; " << r.swarm->stopped_at_cutoff
        << " candidates stopped once they could not beat their particle's best\n";
  }
  if (r.local && r.local->runs.size() > 1) {
    int k = 0;
    for (const auto& run : r.local->runs) out << "  local run " << ++k << ": " << run.report << "\n";
  } else if (r.local) {
    out << "  local: " << r.local->best.report << "\n";
  }
  return out.str();
}

}  // namespace

std::string yarn_summary(const results::YarnFitFile& r) {
  std::ostringstream out;
  out << "yarn fit: " << (r.ok ? "ok" : "FAILED: " + r.message) << "\n";
  out << settings_line(r.settings) << errors_table(r) << measured_and_shape(r) << parameters_table(r);
  if (r.identifiability) out << profile_summary(*r.identifiability);
  out << "  evaluations: " << r.evaluations << "\n" << search_lines(r);
  return out.str();
}

std::string yarn_curves_csv(const results::YarnFitFile& r) {
  std::ostringstream csv;
  csv << std::setprecision(10);
  csv << "direction,sample,stretch,target_S_N_per_m,simulated_S_N_per_m,target_compression,simulated_compression,"
         "weight\n";
  for (const auto& d : r.curves) {
    for (std::size_t i = 0; i < d.stretch.size(); ++i) {
      const auto at = [i](const std::vector<double>& v) { return i < v.size() ? v[i] : k_nan; };
      csv << d.direction << "," << i << "," << d.stretch[i] << "," << at(d.target_S_N_per_m) << ","
          << at(d.simulated_S_N_per_m) << "," << at(d.target_compression) << "," << at(d.simulated_compression) << ","
          << at(d.weight) << "\n";
    }
  }
  return csv.str();
}

}  // namespace yarnfit::reports
