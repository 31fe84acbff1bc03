#include "reports/summaries/shell_summary.hpp"

#include <iomanip>
#include <sstream>
#include <vector>

#include "fabrics_db/text_util.hpp"
#include "reports/metrics/error_metrics.hpp"
#include "reports/summaries/text.hpp"

namespace yarnfit::reports {

using nlohmann::json;

std::string shell_curves_csv(const json& report) {
  // Every value round-trips (the shortest text that reads back exactly), so that errors
  // recomputed from the file equal shell_fit.json's: an error is a small difference of close
  // values, and 10 digits left it 1e-8 off for a close fit.
  std::ostringstream csv;
  csv << "direction,stretch,measured_force_N,simulated_force_N,measured_compression,simulated_compression\n";
  if (!report.contains("directions")) return csv.str();
  for (const auto& d : report["directions"]) {
    const auto& st = d["stretch"];
    auto cell = [&d](const char* key, std::size_t i) -> std::string {
      if (!d.contains(key) || !d[key].is_array() || i >= d[key].size() || !d[key][i].is_number()) return "";
      return db::format_shortest(d[key][i].get<double>());
    };
    for (std::size_t i = 0; i < st.size(); ++i)
      csv << d["direction"].get<std::string>() << "," << db::format_shortest(st[i].get<double>()) << ","
          << cell("measured_force_N", i) << "," << cell("simulated_force_N", i) << ","
          << cell("measured_compression", i) << "," << cell("simulated_compression", i) << "\n";
  }
  return csv.str();
}

namespace {

// A curve of one direction entry, or null when the entry has none.
const json& curve(const json& d, const char* key) {
  static const json none;
  return d.contains(key) ? d[key] : none;
}

}  // namespace

std::string shell_summary(const json& report, double wall_seconds) {
  std::ostringstream out;
  out << "shell fit: " << (report.value("converged", false) ? "converged" : "NOT converged") << "\n";
  out << "  errors (mean abs. error / mean abs. measured value):\n";
  out << "    direction  force        compression\n";
  if (report.contains("directions")) {
    for (const auto& d : report["directions"])
      out << "    " << std::left << std::setw(9) << d["direction"].get<std::string>() << std::right << "  "
          << std::setw(11) << pct(shell_error_pct_json(curve(d, "measured_force_N"), curve(d, "simulated_force_N"))) << "  "
          << std::setw(11)
          << pct(shell_error_pct_json(curve(d, "measured_compression"), curve(d, "simulated_compression"))) << "\n";
  }
  const json& e = report["errors"];
  out << "    all        " << std::setw(11) << pct(number_or_nan(e["stretch_force_pct"])) << "  " << std::setw(11)
      << pct(number_or_nan(e["compression_pct"])) << "   bending (aspect ratio) "
      << (e.contains("bending_pct") && e["bending_pct"].is_number() ? pct(e["bending_pct"].get<double>())
                                                                 : std::string("not fitted"))
      << "\n";
  if (report.contains("errors_reason") && report["errors_reason"].is_string())
    out << "  no errors where the fit failed: " << report["errors_reason"].get<std::string>() << "\n";
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

std::string shell_fit_report(const json& r) {
  std::ostringstream out;
  const json& inplane = r.contains("inplane") ? r["inplane"] : json::object();
  const json& errors = r["errors"];
  const auto strings = [](const json& list) {
    std::vector<std::string> v;
    if (list.is_array())
      for (const auto& s : list) v.push_back(s.get<std::string>());
    return v;
  };
  out << "shell fit of " << r.value("fabric", std::string("?")) << ": "
      << (r.value("converged", false) ? "converged" : "NOT converged") << " after " << r.value("iterations", 0)
      << " iterations, " << number_text(inplane.value("timing_s", r.value("timing_s", json())), 3) << " s\n";
  const double force = number_or_nan(errors["stretch_force_pct"]);
  out << "  force error " << (std::isfinite(force) ? db::format_g(force, 3) + " %" : std::string("-"))
      << ", compression error ";
  if (!inplane.value("compression_measured", true)) out << "not measured";
  else out << (errors["compression_pct"].is_number() ? db::format_g(errors["compression_pct"].get<double>(), 3) + " %"
                                                     : std::string("-"));
  out << "\n";
  if (inplane.contains("errors_reason") && inplane["errors_reason"].is_string())
    out << "  no errors: " << inplane["errors_reason"].get<std::string>() << "\n";
  const json& starts = r.contains("starts") ? r["starts"] : json::array();
  const int chosen = r.value("chosen_start", -1);
  if (starts.size() > 1 && chosen >= 0) {
    const int restarts = r.value("restarts", 0);
    out << "  best of " << starts.size() << " data-based starts: "
        << starts[static_cast<std::size_t>(chosen)]["name"].get<std::string>()
        << (restarts > 0 ? ", " + std::to_string(restarts) + " restart(s) after stalls" : std::string()) << "\n";
  }
  if (r.contains("directions"))
    for (const auto& d : r["directions"])
      out << "  " << d["direction"].get<std::string>() << ": fitted up to s = "
          << number_text(d["fitted_max_stretch"], 3) << " of " << number_text(d["measured_max_stretch"], 3)
          << " measured\n";
  for (const auto& n : strings(inplane.value("not_identified", json()))) out << "  not identified: " << n << "\n";
  for (const auto& n : strings(r.value("weakly_identified", json()))) out << "  weakly identified: " << n << "\n";
  for (const auto& b : strings(inplane.value("at_bounds", json())))
    out << "  WARNING: " << b << " ended on a search bound\n";
  if (r.contains("bending")) {
    const json& b = r["bending"];
    const double bending = number_or_nan(errors["bending_pct"]);
    out << "  bending: " << (b.value("converged", false) ? "converged" : "NOT converged") << ", aspect-ratio error "
        << (std::isfinite(bending) ? db::format_g(bending, 3) + " %" : std::string("-")) << ", "
        << number_text(b.value("timing_s", json()), 3) << " s\n";
    for (const auto& s : strings(b.value("fallback_starts", json()))) out << "  WARNING: " << s << "\n";
    for (const auto& s : strings(b.value("at_bounds", json()))) out << "  WARNING: " << s << " ended on a search bound\n";
  }
  return out.str();
}

}  // namespace yarnfit::reports
