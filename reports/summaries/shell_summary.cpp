#include "reports/summaries/shell_summary.hpp"

#include <iomanip>
#include <sstream>
#include <vector>

#include "fabrics_db/text_util.hpp"
#include "reports/summaries/text.hpp"

namespace yarnfit::reports {

std::string shell_curves_csv(const results::ShellFitFile& report) {
  // Every value round-trips (the shortest text that reads back exactly), so that errors
  // recomputed from the file equal shell_fit.json's: an error is a small difference of close
  // values, and 10 digits left it 1e-8 off for a close fit.
  std::ostringstream csv;
  csv << "direction,stretch,measured_force_N,simulated_force_N,measured_compression,simulated_compression\n";
  for (const auto& d : report.directions) {
    auto cell = [](const std::vector<double>& curve, std::size_t i) -> std::string {
      if (i >= curve.size() || std::isnan(curve[i])) return "";
      return db::format_shortest(curve[i]);
    };
    for (std::size_t i = 0; i < d.stretch.size(); ++i)
      csv << d.direction << "," << db::format_shortest(d.stretch[i]) << "," << cell(d.measured_force_N, i) << ","
          << cell(d.simulated_force_N, i) << "," << cell(d.measured_compression, i) << ","
          << cell(d.simulated_compression, i) << "\n";
  }
  return csv.str();
}

std::string shell_summary(const results::ShellFitFile& report, double wall_seconds) {
  std::ostringstream out;
  out << "shell fit: " << (report.converged ? "converged" : "NOT converged") << "\n";
  out << "  errors (mean abs. error / mean abs. measured value):\n";
  out << "    direction  force        compression\n";
  for (const auto& d : report.directions) {
    const results::ShellDirectionErrors e = report.direction_errors(d.direction);
    out << "    " << std::left << std::setw(9) << d.direction << std::right << "  " << std::setw(11)
        << pct(e.stretch_force_pct) << "  " << std::setw(11) << pct(e.compression_pct) << "\n";
  }
  const results::ShellErrors& e = report.errors;
  out << "    all        " << std::setw(11) << pct(e.stretch_force_pct) << "  " << std::setw(11) << pct(e.compression_pct)
      << "   bending (aspect ratio) " << (std::isnan(e.bending_pct) ? std::string("not fitted") : pct(e.bending_pct))
      << "\n";
  if (!report.errors_reason.empty()) out << "  no errors where the fit failed: " << report.errors_reason << "\n";
  out << "  parameters (N/m; k_theta in N*m):";
  std::vector<std::string> not_fitted;
  for (const auto& [k, v] : report.params) {
    if (v) out << " " << k << " = " << number_text(*v);
    else not_fitted.push_back(k);
  }
  if (!not_fitted.empty()) out << "; not fitted: " << db::join_words(not_fitted, " and ");
  out << "\n  time: " << db::format_g(wall_seconds, 3) << " s (fits " << number_text(report.timing_s, 3)
      << " s, the rest reading the record and writing the uniform targets)\n";
  return out.str();
}

namespace {

// A FAB record's tests: k_θ from the loop bends, then each test, fitted or held out.
void fab_summary(std::ostringstream& out, const results::FabFitDetails& fab) {
  const auto pct_text = [](double v) { return std::isfinite(v) ? db::format_g(v, 3) + " %" : std::string("-"); };
  for (const auto& b : fab.bends)
    out << "  loop bends, " << b.direction << ": k_theta " << number_text(b.ktheta) << " N*m (misfit doubled at "
        << number_text(b.ktheta_low) << " and " << number_text(b.ktheta_high) << "), force error "
        << pct_text(b.force_pct) << (b.converged ? "" : " (NOT converged: " + b.message + ")")
        << (b.on_bound ? " (WARNING: on its search bound)" : "") << ", " << b.evaluations << " evaluations, "
        << number_text(b.timing_s, 3) << " s\n";
  out << "  FAB tests against every loading branch (held out: " << db::join_words(fab.held_out, " and ") << "):\n";
  for (const char* dir : {"weft", "bias", "warp"}) {
    std::string line;
    for (const auto& t : fab.tests)
      if (t.direction == dir) line += "  " + t.test + (t.held_out ? "* " : " ") + pct_text(t.force_pct);
    if (!line.empty()) out << "    " << dir << ":" << line << "\n";
  }
  out << "    (* held out and predicted; a bend's zero is a free offset)\n";
}

}  // namespace

std::string shell_fit_report(const results::ShellFitFile& r) {
  std::ostringstream out;
  const results::InplaneDetails inplane = r.inplane.value_or(results::InplaneDetails{r.timing_s, {}, {}, true, ""});
  out << "shell fit of " << (r.fabric.empty() ? std::string("?") : r.fabric) << ": "
      << (r.converged ? "converged" : "NOT converged") << " after " << r.iterations << " iterations, "
      << number_text(inplane.timing_s, 3) << " s\n";
  const double force = r.errors.stretch_force_pct;
  out << "  force error " << (std::isfinite(force) ? db::format_g(force, 3) + " %" : std::string("-"))
      << ", compression error ";
  if (!inplane.compression_measured) out << "not measured";
  else out << (std::isnan(r.errors.compression_pct) ? std::string("-") : db::format_g(r.errors.compression_pct, 3) + " %");
  out << "\n";
  if (!inplane.errors_reason.empty()) out << "  no errors: " << inplane.errors_reason << "\n";
  const int chosen = r.chosen_start;
  if (r.starts.size() > 1 && chosen >= 0 && static_cast<std::size_t>(chosen) < r.starts.size()) {
    out << "  best of " << r.starts.size() << " data-based starts: " << r.starts[static_cast<std::size_t>(chosen)].name
        << (r.restarts > 0 ? ", " + std::to_string(r.restarts) + " restart(s) after stalls" : std::string()) << "\n";
  }
  for (const auto& d : r.directions)
    out << "  " << d.direction << ": fitted up to s = " << number_text(d.fitted_max_stretch, 3) << " of "
        << number_text(d.measured_max_stretch, 3) << " measured\n";
  for (const auto& n : inplane.not_identified) out << "  not identified: " << n << "\n";
  for (const auto& n : r.weakly_identified) out << "  weakly identified: " << n << "\n";
  for (const auto& b : inplane.at_bounds) out << "  WARNING: " << b << " ended on a search bound\n";
  if (r.bending) {
    const results::BendingDetails& b = *r.bending;
    const double bending = r.errors.bending_pct;
    out << "  bending: " << (b.converged ? "converged" : "NOT converged") << ", aspect-ratio error "
        << (std::isfinite(bending) ? db::format_g(bending, 3) + " %" : std::string("-")) << ", "
        << number_text(b.timing_s, 3) << " s\n";
    for (const auto& s : b.fallback_starts) out << "  WARNING: " << s << "\n";
    for (const auto& s : b.at_bounds) out << "  WARNING: " << s << " ended on a search bound\n";
  }
  if (r.fab) fab_summary(out, *r.fab);
  return out.str();
}

}  // namespace yarnfit::reports
