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

namespace yarnfit::reports {

namespace {

using nlohmann::json;
using results::number_or_nan;
constexpr double k_inf = std::numeric_limits<double>::infinity();
constexpr double k_nan = std::numeric_limits<double>::quiet_NaN();

// The optimised parameters in the order of the fit's parameter space (SPEC §3: p = {ks1, ε̄s,
// kb, R1, kc1}); JSON objects sort their keys, the tables keep this order.
const char* const k_fitted[] = {"ks1", "eps_s", "kb", "R1", "kc1"};

const json& member(const json& j, const char* key) {
  static const json none;
  return j.is_object() && j.contains(key) ? j[key] : none;
}

// A factor written as a number, or as null with a flag saying whether it was unbounded.
double factor(const json& entry, const char* key, const char* free_flag) {
  const json& v = member(entry, key);
  if (v.is_number()) return v.get<double>();
  return member(entry, free_flag).is_boolean() && member(entry, free_flag).get<bool>() ? k_inf : k_nan;
}

// A range factor f as the user reads it: "±4.2 %" when small, "÷/× 3.1" when not.
std::string range(double f) {
  if (std::isnan(f)) return "-";
  if (std::isinf(f)) return "unbounded";
  if (f > 100.0) return "÷/× > 100";
  return f < 1.5 ? "±" + db::format_g(100.0 * (f - 1.0), 2) + " %" : "÷/× " + db::format_g(f, 2);
}

// Which fitted values the targets stand behind (yarn_fit.json's `identifiability`).
std::string profile_summary(const json& p) {
  const double step = number_or_nan(member(p, "step"));
  if (!std::isfinite(step) || step == 0.0) return {};  // the profile was not asked for
  std::ostringstream out;
  const std::string message = p.value("message", std::string());
  if (!p.value("computed", false)) {
    out << "  identifiability: not computed (" << message << ")\n";
    return out.str();
  }
  const double g_fit = number_or_nan(member(p, "objective"));
  const std::string f = db::format_g(1.0 + step, 3);
  // From the Gauss–Newton step's exact Jacobian at the fit, the one-at-a-time g values are its
  // model's; from evaluations (the other local steps), they were simulated.
  const bool model = p.value("from", std::string()) == "jacobian";
  out << "  identifiability (g = " << db::format_g(g_fit, 3)
      << " at the fit; range: how far a parameter moves before g doubles; "
      << (model ? "from the exact Jacobian at the fit" : "from simulations at ÷/× " + f) << "):\n"
      << "    parameter  g at ÷" << f << " / ×" << f << (model ? " (model)" : "") << "    range, others re-fitted   others held\n";
  std::string downhill;
  const json& entries = member(p, "parameters");
  for (const char* name : k_fitted) {
    if (!entries.is_object() || !entries.contains(name)) continue;
    const json& e = entries[name];
    // A side that failed is written null: its g was +inf.
    const double g_lower = e["objective_lower"].is_number() ? e["objective_lower"].get<double>() : k_inf;
    const double g_upper = e["objective_upper"].is_number() ? e["objective_upper"].get<double>() : k_inf;
    const std::string g = db::format_g(g_lower, 3) + " / " + db::format_g(g_upper, 3);
    out << "    " << std::left << std::setw(9) << name << "  " << std::setw(22) << g << std::right << std::setw(19)
        << range(factor(e, "range_factor", "free")) << std::setw(16) << range(factor(e, "range_alone_factor", "free_alone"))
        << "\n";
    if (std::min(g_lower, g_upper) < 0.99 * g_fit) downhill += (downhill.empty() ? "" : ", ") + std::string(name);
  }
  out << "    a range wider than the accuracy you need: the targets do not pin that parameter, and its value is one "
         "of many that fit as well\n";
  // The ranges assume the fit is a minimum; where a 10 % step lowers g it is not.
  if (!downhill.empty())
    out << "    g falls by more than 1 % with " << downhill
        << " moved: the fit is not at a minimum there (ranges are rough; more --local-evaluations may help)\n";
  if (!message.empty()) out << "    incomplete: " << message << "\n";
  return out.str();
}

std::string settings_line(const json& s) {
  std::ostringstream out;
  const bool swarm = s.value("swarm", true);
  const int nodes = s.value("local_compression_nodes", 0);
  const json& staged = member(s, "staged");
  const auto stage = [&](const char* name) {
    const json& st = member(staged, name);
    return std::to_string(st.value("particles", 0)) + " x " + std::to_string(st.value("iterations", 0)) + " on " +
           std::to_string(st.value("samples", 0)) + " samples";
  };
  std::string global;
  if (!swarm) global = s.contains("start") ? "no global search, started from --start; " : "no global search; ";
  else if (s.value("global_method", std::string("swarm")) == "staged")
    global = "staged search (contact " + stage("contact") + ", all " + stage("all") + ", " +
             std::to_string(staged.value("starts", 0)) + " local starts); ";
  else
    global = "swarm " + std::to_string(s.value("particles", 0)) + " particles x " + std::to_string(s.value("iterations", 0)) +
             " iterations, " + std::to_string(s.value("swarm_samples", 0)) + " samples per direction; ";
  const std::string method = s.value("local_method", std::string("?"));
  out << "  settings: " << global << "local step " << method
      << (method == "gauss-newton"
              ? " (at most " + std::to_string(member(s, "alternation").value("max_rounds", 0)) + " rounds)"
              : ", at most " + std::to_string(s.value("local_evaluations", 0)) + " evaluations")
      << ", " << s.value("local_samples", 0) << " samples per direction; seed "
      << s.value("seed", std::uint64_t{0}) << (s.value("linear_stretch", false) ? "; linear stretch (ks1 = ks2, eps_s = 0)" : "")
      << (s.value("rest_shape", true) ? "" : "; no rest-shape heuristic")
      << (s.value("rest_period", false) ? "; period relaxed per candidate" : "")
      << (nodes == 0 ? std::string("; c* at every sample") : "; c* at " + std::to_string(nodes) + " samples, linear between")
      << "\n";
  return out.str();
}

}  // namespace

std::string yarn_summary(const json& r) {
  std::ostringstream out;
  const bool ok = r.value("ok", false);
  out << "yarn fit: " << (ok ? "ok" : "FAILED: " + r.value("message", std::string())) << "\n";
  out << settings_line(member(r, "settings"));
  out << "  errors (mean abs. error / largest comfort-range target):\n";
  out << "    direction  stress comfort  stress full  compression  bending (checked, not fitted)\n";
  const json& by_direction = member(r, "errors_by_direction");
  const json& curves = member(r, "curves");
  if (curves.is_array()) {
    for (const auto& c : curves) {
      const std::string name = c["direction"].get<std::string>();
      const json& e = member(by_direction, name.c_str());
      out << "    " << std::left << std::setw(9) << name << std::right << "  " << std::setw(14)
          << pct(number_or_nan(member(e, "stress_comfort_pct"))) << "  " << std::setw(11)
          << pct(number_or_nan(member(e, "stress_full_pct"))) << "  " << std::setw(11)
          << pct(number_or_nan(member(e, "compression_pct"))) << "  " << std::setw(8)
          << pct(number_or_nan(member(e, "bending_pct"))) << "\n";
    }
  }
  if (r.contains("errors_reason") && r["errors_reason"].is_string())
    out << "  no errors: " << r["errors_reason"].get<std::string>() << "\n";
  const json& check = member(r, "bending_check");
  if (check.is_object() && !check.value("ok", true) && !check.value("message", std::string()).empty())
    out << "  bending check failed: " << check["message"].get<std::string>() << "\n";

  const json& params = member(r, "params");
  const json& bounds = member(r, "bounds");
  std::vector<std::string> on_bound;
  for (const auto& b : member(r, "on_bound")) on_bound.push_back(b.get<std::string>());
  out << "  parameters (SI):\n";
  for (const char* name : k_fitted) {
    if (!bounds.is_object() || !bounds.contains(name)) continue;
    const json& b = bounds[name];
    const bool on = std::find(on_bound.begin(), on_bound.end(), name) != on_bound.end();
    const double v = number_or_nan(member(params, name));
    out << "    " << std::left << std::setw(6) << name << std::right << " = " << std::setw(12) << db::format_g(v, 5)
        << "   in [" << db::format_g(b["lower"].get<double>(), 4) << ", " << db::format_g(b["upper"].get<double>(), 4)
        << "]" << (b.value("log", false) ? " log" : "") << (on ? "   ON A BOUND" : "") << "\n";
  }
  for (const char* k : {"ks1", "eps_s", "ks2", "kc2", "R2"}) {
    const bool optimised = bounds.is_object() && bounds.contains(k);
    if (!optimised && params.is_object() && params.contains(k))
      out << "    " << std::left << std::setw(6) << k << std::right << " = " << std::setw(12)
          << db::format_g(params[k].get<double>(), 5) << "   fixed\n";
  }
  out << profile_summary(member(r, "identifiability"));
  out << "  evaluations: " << r.value("evaluations", 0) << "\n";
  const json& t = member(r, "timing_s");
  const bool profiled = member(r, "identifiability").is_object() && r["identifiability"].value("computed", false);
  out << "  time: global " << number_text(member(t, "swarm"), 3) << " s, local " << number_text(member(t, "local"), 3)
      << " s" << (profiled ? ", profile " + number_text(member(t, "profile"), 3) + " s" : std::string()) << ", total "
      << number_text(member(t, "total"), 3) << " s\n";
  const json& global = member(member(r, "global"), "stages");
  if (global.is_array() && !global.empty()) {
    for (const auto& st : global)
      out << "  " << st.value("stage", std::string()) << ": "
          << (st.value("report", std::string()).empty() ? std::to_string(st.value("evaluations", 0)) + " evaluations"
                                                         : st.value("report", std::string()))
          << ", best g " << number_text(member(st, "best"), 4)
          << (st.value("stopped_at_cutoff", 0) > 0
                  ? "; " + std::to_string(st.value("stopped_at_cutoff", 0)) +
                        " candidates stopped once they could not beat their particle's best"
                  : std::string())
          << "\n";
  } else {
    const json& swarm = member(r, "swarm");
    if (swarm.is_object() && !member(swarm, "history").empty())
      out << "  swarm: " << swarm.value("report", std::string()) << "; " << swarm.value("stopped_at_cutoff", 0)
          << " candidates stopped once they could not beat their particle's best\n";
  }
  const json& local = member(r, "local");
  const json& runs = member(local, "runs");
  if (runs.is_array() && runs.size() > 1) {
    int k = 0;
    for (const auto& run : runs) out << "  local run " << ++k << ": " << run.value("report", std::string()) << "\n";
  } else if (local.is_object()) {
    out << "  local: " << local.value("report", std::string()) << "\n";
  }
  return out.str();
}

std::string yarn_curves_csv(const json& r) {
  std::ostringstream csv;
  csv << std::setprecision(10);
  csv << "direction,sample,stretch,target_S_N_per_m,simulated_S_N_per_m,target_compression,simulated_compression,"
         "weight\n";
  const json& curves = member(r, "curves");
  if (!curves.is_array()) return csv.str();
  for (const auto& d : curves) {
    const json& stretch = member(d, "stretch");
    for (std::size_t i = 0; i < stretch.size(); ++i) {
      const auto at = [&d, i](const char* key) {
        const json& v = member(d, key);
        return v.is_array() && i < v.size() ? number_or_nan(v[i]) : k_nan;
      };
      csv << d["direction"].get<std::string>() << "," << i << "," << number_or_nan(stretch[i]) << ","
          << at("target_S_N_per_m") << "," << at("simulated_S_N_per_m") << "," << at("target_compression") << ","
          << at("simulated_compression") << "," << at("weight") << "\n";
    }
  }
  return csv.str();
}

}  // namespace yarnfit::reports
