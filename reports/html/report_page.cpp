#include "reports/html/report_page.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "reports/html/svg_plot.hpp"
#include "reports/html/tile_drawing.hpp"
#include "results/metrics/error_metrics.hpp"

namespace yarnfit::reports {

using results::number_or_nan;
using svg::escape;
using svg::number_label;

namespace {

const char* const k_css = R"(
body{font-family:"DejaVu Sans",Arial,sans-serif;font-size:14px;color:#222;max-width:1180px;margin:20px auto;padding:0 16px;background:#fafafa}
h1{font-size:24px;margin:0 0 4px} h2{font-size:19px;margin:28px 0 8px;border-bottom:2px solid #ccc;padding-bottom:3px}
h3{font-size:16px;margin:18px 0 6px} .meta{color:#666} .note{fill:#777;font-size:12px;font-style:italic}
p.note{color:#666;font-size:12px;font-style:italic}
table{border-collapse:collapse;margin:6px 0 12px;background:#fff} th,td{border:1px solid #ccc;padding:3px 7px;text-align:right}
th{background:#eef2f5} td.l,th.l{text-align:left} tr.failed td{background:#fde9e2}
.good{background:#dcebd5} .bad{background:#fbe3d6} .fail{color:#a33;font-weight:bold}
section.fabric{border:1px solid #ddd;background:#fff;padding:8px 14px 14px;margin:14px 0;border-radius:4px}
.plots{display:flex;flex-wrap:wrap;gap:10px;align-items:flex-start}
svg.plot{background:#fff;border:1px solid #e2e2e2}
svg text{font-family:"DejaVu Sans",Arial,sans-serif;font-size:11px;fill:#222}
svg text.plot-title{font-size:13px;font-weight:bold} svg text.axis-label{font-size:12px}
svg text.group-label{font-weight:bold;font-size:12px} svg text.flag{fill:#D55E00;font-weight:bold}
svg text.tick{fill:#444;font-size:10px}
ul.toc{columns:4;font-size:13px} code{font-size:12px}
div.families{display:flex;flex-wrap:wrap;gap:4px 28px;align-items:flex-start} div.family p.note{max-width:420px}
)";

const std::string& direction_colour(const std::string& d) {
  static const std::map<std::string, std::string> c{{"weft", "#0072B2"}, {"bias", "#009E73"}, {"warp", "#D55E00"}};
  static const std::string other = "#000000";
  const auto it = c.find(d);
  return it == c.end() ? other : it->second;
}

std::string pct_cell(double v, bool shade = true) {
  if (!std::isfinite(v)) return "<td>–</td>";
  std::ostringstream s;
  s << "<td" << (shade ? (v <= k_good_fit_pct ? " class=\"good\"" : " class=\"bad\"") : "") << ">"
    << number_label(v) << "</td>";
  return s.str();
}

std::string seconds_text(double s) {
  if (!std::isfinite(s)) return "–";
  std::ostringstream o;
  if (s < 60) o << number_label(s) << " s";
  else if (s < 3600) o << number_label(s / 60) << " min";
  else o << number_label(s / 3600) << " h";
  return o.str();
}

std::string anchor(const std::string& id) {
  std::string a = "fabric-";
  for (char c : id) a += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return a;
}

std::string attrs(const std::string& plot, const std::string& key = "", const std::string& value = "") {
  std::string a = "class=\"plot\" data-plot=\"" + plot + "\"";
  if (!key.empty()) a += " data-" + key + "=\"" + escape(value) + "\"";
  return a;
}

// The colour of each family, in the order of the report.
std::map<std::string, std::string> family_colours(const ReportData& d) {
  std::map<std::string, std::string> c;
  for (std::size_t i = 0; i < d.families.size(); ++i)
    c[d.families[i].family] = svg::palette()[i % svg::palette().size()];
  return c;
}

std::vector<std::size_t> metric_indices(const char* stage, bool with_bending_shell = true) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < k_metrics.size(); ++i)
    if (std::string_view(k_metrics[i].stage) == stage &&
        (with_bending_shell || std::string_view(k_metrics[i].key) != "shell_aspect_ratio_pct"))
      out.push_back(i);
  return out;
}

// ---- summary ---------------------------------------------------------------------------

void summary(std::ostringstream& h, const ReportData& d) {
  int done = 0, failed = 0, other = 0;
  for (const auto& r : d.fabrics) (r.status == "done" ? done : r.status == "failed" ? failed : other)++;
  h << "<h2 id=\"summary\">Summary</h2><p>" << d.fabrics.size() << " fabrics in " << d.families.size()
    << " famil" << (d.families.size() == 1 ? "y" : "ies") << ": <b>" << done << " fitted</b>, <b"
    << (failed ? " class=\"fail\"" : "") << ">" << failed << " failed</b>"
    << (other ? ", " + std::to_string(other) + " not finished (running or queued)" : std::string()) << ". "
    << "Errors are the thesis's (Fig. 6.13, 6.15): shell figures are the mean absolute error over the "
       "mean absolute measured value; yarn figures the mean absolute error over the largest target in "
       "the comfort range; green cells are within "
    << number_label(k_good_fit_pct) << " %.</p>";
  h << "<table><tr><th class=\"l\">run</th><th class=\"l\">source</th><th>fabrics</th><th>done</th><th>failed</th>"
       "<th>fit time</th></tr>";
  for (const auto& r : d.run_summaries)
    h << "<tr><td class=\"l\">" << escape(r.label) << "</td><td class=\"l\"><code>" << escape(r.source)
      << "</code></td><td>" << r.fabrics << "</td><td>" << r.done << "</td><td>" << r.failed << "</td><td>"
      << seconds_text(r.seconds) << "</td></tr>";
  h << "</table>";
  h << "<table><tr><th class=\"l\">family</th><th>fabrics</th><th>failed</th><th>with yarn stage</th></tr>";
  for (const auto& f : d.families) {
    int yarn = 0;
    for (const auto& r : d.fabrics)
      if (r.family == f.family && r.has_yarn()) ++yarn;
    h << "<tr><td class=\"l\">" << escape(family_name(f.family)) << "</td><td>" << f.fabrics << "</td><td>" << f.failed
      << "</td><td>" << yarn << "</td></tr>";
  }
  h << "</table>";
  bool any_failed = false;
  for (const auto& r : d.fabrics)
    if (r.status != "done") any_failed = true;
  if (any_failed) {
    h << "<h3>Not fitted</h3><table><tr><th class=\"l\">fabric</th><th class=\"l\">family</th><th "
         "class=\"l\">status</th><th class=\"l\">reason</th></tr>";
    for (const auto& r : d.fabrics)
      if (r.status != "done")
        h << "<tr class=\"failed\"><td class=\"l\"><a href=\"#" << anchor(r.id) << "\">" << escape(r.id)
          << "</a></td><td class=\"l\">" << escape(family_name(r.family)) << "</td><td class=\"l\">" << escape(r.status)
          << "</td><td class=\"l\">" << escape(r.error.empty() ? "(no reason recorded)" : r.error) << "</td></tr>";
    h << "</table>";
  }
  // Time per stage over the fabrics of the report.
  h << "<h3>Time per stage</h3><table><tr><th class=\"l\">stage</th><th>fabrics</th><th>total</th><th>mean</th>"
       "<th>longest</th></tr>";
  for (std::size_t i = 0; i < k_times.size(); ++i) {
    double sum = 0, longest = 0;
    int n = 0;
    for (const auto& r : d.fabrics)
      if (std::isfinite(r.times[i])) sum += r.times[i], longest = std::max(longest, r.times[i]), ++n;
    if (n == 0) continue;
    h << "<tr><td class=\"l\">" << k_times[i].label << "</td><td>" << n << "</td><td>" << seconds_text(sum)
      << "</td><td>" << seconds_text(sum / n) << "</td><td>" << seconds_text(longest) << "</td></tr>";
  }
  h << "</table>";
  if (!d.problems.empty()) {
    h << "<h3>Files left out</h3><ul>";
    for (const auto& p : d.problems) h << "<li>" << escape(p) << "</li>";
    h << "</ul>";
  }
}

// ---- families --------------------------------------------------------------------------

void family_tables(std::ostringstream& h, const ReportData& d) {
  h << "<h2 id=\"families\">Errors per family</h2><p class=\"note\">Mean ± standard deviation (over n − 1; "
       "none for one fabric), min and max over the fabrics with a figure, and how many are within "
    << number_label(k_good_fit_pct) << " % (cf. the thesis's Table 6.1).</p>";
  h << "<div class=\"families\">";
  for (const auto& f : d.families) {
    h << "<div class=\"family\"><h3>" << escape(family_name(f.family)) << " <span class=\"meta\">(" << f.fabrics << " fabric"
      << (f.fabrics == 1 ? "" : "s") << (f.failed ? ", " + std::to_string(f.failed) + " failed" : std::string())
      << ")</span></h3>";
    h << "<table class=\"family-table\" data-family=\"" << escape(f.family)
      << "\"><tr><th class=\"l\">stage</th><th class=\"l\">error [%]</th><th>n</th><th>mean ± sd</th><th>min</th>"
         "<th>max</th><th>≤ "
      << number_label(k_good_fit_pct) << " %</th></tr>";
    // Metrics no fabric of the family has (no pear-loop tests, no yarn stage) are named below
    // the table instead of filling it with empty rows.
    std::vector<std::string> none;
    for (std::size_t i = 0; i < k_metrics.size(); ++i) {
      const MetricStats& s = f.metrics[i];
      if (s.n == 0) {
        none.push_back(std::string(k_metrics[i].stage) + " " + k_metrics[i].label);
        continue;
      }
      h << "<tr><td class=\"l\">" << k_metrics[i].stage << "</td><td class=\"l\">" << k_metrics[i].label << "</td><td>"
        << s.n << "</td>";
      h << "<td>" << number_label(s.mean) << (std::isfinite(s.sd) ? " ± " + number_label(s.sd) : std::string())
        << "</td><td>" << number_label(s.min) << "</td><td>" << number_label(s.max) << "</td><td>" << s.within << " of "
        << s.n << "</td></tr>";
    }
    h << "</table>";
    if (!none.empty()) {
      h << "<p class=\"note\">No figure (not measured or not run): ";
      for (std::size_t k = 0; k < none.size(); ++k) h << (k ? ", " : "") << escape(none[k]);
      h << ".</p>";
    }
    h << "</div>";
  }
  h << "</div>";
}

svg::DotRow dot_row(const FabricRow& r, const std::vector<std::size_t>& metrics, const std::string& colour) {
  svg::DotRow row{r.id + (r.status == "done" ? "" : " (" + r.status + ")"), family_name(r.family), colour, {}};
  for (std::size_t i : metrics) row.values.push_back(r.metrics[i]);
  return row;
}

void overview_plots(std::ostringstream& h, const ReportData& d) {
  const auto colours = family_colours(d);
  h << "<h2 id=\"overview\">Errors per fabric</h2><div class=\"plots\">";
  const auto plot = [&](const char* stage, const char* title, const char* name) {
    svg::DotPlot p;
    p.title = title;
    p.x_label = "error [%]  (shaded: ≤ " + number_label(k_good_fit_pct) + " %)";
    const auto idx = metric_indices(stage);
    for (std::size_t i : idx) p.metrics.push_back(k_metrics[i].label);
    std::set<std::string> shown;
    for (const auto& r : d.fabrics)
      if (std::string_view(stage) == "shell" || (std::string_view(stage) == "yarn" && r.has_yarn()) || r.has_end_to_end()) {
        p.rows.push_back(dot_row(r, idx, colours.at(r.family)));
        shown.insert(r.family);
      }
    for (const auto& f : d.families)
      if (shown.count(f.family)) p.group_legend.emplace_back(family_name(f.family), colours.at(f.family));
    p.attributes = attrs("overview", "stage", name);
    h << svg::render(p);
  };
  plot("shell", "Shell errors (cf. Fig. 6.13): marker = metric, colour = family", "shell");
  if (d.has_yarn()) plot("yarn", "Yarn errors (cf. Fig. 6.15): marker = metric, colour = family", "yarn");
  if (d.has_end_to_end())
    plot("end-to-end", "End to end: the fitted yarn models against the measured curves, marker = metric, colour = family",
         "end-to-end");
  h << "</div>";
}

void family_plots(std::ostringstream& h, const ReportData& d) {
  h << "<h2 id=\"family-plots\">Each family</h2><div class=\"plots\">";
  for (const auto& f : d.families) {
    svg::DotPlot p;
    p.title = family_name(f.family) + ": every error, marker and colour = metric";
    p.x_label = "error [%]  (shaded: ≤ " + number_label(k_good_fit_pct) + " %)";
    // The metrics some fabric of the family has (always the shell force, so that a family of
    // failed fabrics still gets its plot).
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < k_metrics.size(); ++i)
      if (f.metrics[i].n > 0 || i == 0) idx.push_back(i);
    for (std::size_t i : idx) p.metrics.push_back(std::string(k_metrics[i].stage) + " " + k_metrics[i].label);
    for (const auto& r : d.fabrics)
      if (r.family == f.family) p.rows.push_back(dot_row(r, idx, ""));
    for (auto& r : p.rows) r.group.clear();
    p.width = 560;
    p.attributes = attrs("family", "family", f.family);
    h << svg::render(p);
  }
  h << "</div>";
}

// ---- what accuracy costs ----------------------------------------------------------------

void cost_section(std::ostringstream& h, const ReportData& d) {
  std::vector<std::string> compared;
  for (const auto& [id, rows] : d.by_run)
    if (rows.size() >= 2) compared.push_back(id);
  h << "<h2 id=\"cost\">What accuracy costs</h2>";
  if (compared.empty()) {
    h << "<p class=\"note\">One run per fabric: give `yarnfit report` several runs over the same fabrics (for "
         "example two batches with different swarm settings) to compare their errors and times here.</p>";
    return;
  }
  // The runs that hold a compared fabric (a run over other fabrics has nothing to compare).
  std::vector<std::string> runs;
  std::vector<int> run_index;
  for (std::size_t k = 0; k < d.run_summaries.size(); ++k) {
    bool used = false;
    for (const auto& id : compared)
      for (const auto& r : d.by_run.at(id)) used = used || r.run_index == static_cast<int>(k);
    if (!used) continue;
    runs.push_back(d.run_summaries[k].label);
    run_index.push_back(static_cast<int>(k));
  }
  h << "<p>Each fabric in several runs: its headline error (yarn comfort-range stress where the yarn stage ran, "
       "else shell force) and its fit time.</p><table><tr><th class=\"l\">fabric</th>";
  for (const auto& r : runs) h << "<th>" << escape(r) << " error [%]</th><th>" << escape(r) << " time</th>";
  h << "</tr>";
  for (const auto& id : compared) {
    h << "<tr><td class=\"l\">" << escape(id) << "</td>";
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const FabricRow* row = nullptr;
      for (const auto& r : d.by_run.at(id))
        if (r.run_index == run_index[k]) row = &r;
      if (!row) h << "<td>–</td><td>–</td>";
      else h << pct_cell(row->headline_pct()) << "<td>" << seconds_text(row->total_seconds()) << "</td>";
    }
    h << "</tr>";
  }
  h << "</table>";
  svg::XYPlot p;
  p.title = "Error against fit time, one marker per fabric and run";
  p.x_label = "fit time [s]";
  p.y_label = "headline error [%]";
  p.x_log = true;
  p.width = 620;
  p.height = 340;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    svg::Series s;
    s.label = runs[k];
    s.colour = svg::palette()[k % svg::palette().size()];
    s.line = false;
    s.markers = true;
    s.marker = svg::marker_for(k);
    for (const auto& id : compared)
      for (const auto& r : d.by_run.at(id))
        if (r.run_index == run_index[k]) s.x.push_back(r.total_seconds()), s.y.push_back(r.headline_pct());
    p.series.push_back(s);
  }
  // Each fabric's runs joined by a thin grey line: its own trade-off of time against error.
  for (const auto& id : compared) {
    svg::Series s;
    s.colour = "#bbbbbb";
    for (const auto& r : d.by_run.at(id)) s.x.push_back(r.total_seconds()), s.y.push_back(r.headline_pct());
    p.series.insert(p.series.begin(), s);
  }
  p.attributes = attrs("cost");
  h << svg::render(p);
}

// ---- one fabric -------------------------------------------------------------------------

svg::XYPlot curve_plot(const char* title, const char* x_label, const char* y_label) {
  svg::XYPlot p;
  p.title = title;
  p.x_label = x_label;
  p.y_label = y_label;
  return p;
}

// A measured (or target) curve drawn as markers and its model as a line, in the direction's
// colour: `data` and `model` are one direction's curves.
struct CurvePair {
  svg::XYPlot* plot;
  const std::vector<double>& data;
  const std::vector<double>& model;
  double scale;  // of the values (fractions to %)
  const char* data_label;
  const char* model_label;
};

std::vector<double> scaled(const std::vector<double>& values, double scale) {
  std::vector<double> v;
  for (double x : values) v.push_back(x * scale);
  return v;
}

void add_direction(const std::string& dir, const std::vector<double>& x_values, double x_scale,
                   std::initializer_list<CurvePair> pairs) {
  const auto x = scaled(x_values, x_scale);
  for (const CurvePair& c : pairs) {
    auto data = scaled(c.data, c.scale), model = scaled(c.model, c.scale);
    if (!data.empty()) c.plot->series.push_back({dir + " " + c.data_label, x, data, direction_colour(dir), false, true});
    if (!model.empty())
      c.plot->series.push_back({dir + " " + c.model_label, x, model, direction_colour(dir), true, false});
  }
}

void shell_plots(std::ostringstream& h, const FabricRow& r) {
  const results::ShellFitFile& s = *r.outputs->shell;
  if (s.directions.empty()) return;
  svg::XYPlot force = curve_plot("Stretch test: force", "stretch s [%]", "force [N]");
  svg::XYPlot comp = curve_plot("Stretch test: lateral compression", "stretch s [%]", "compression c [%]");
  for (const auto& d : s.directions)
    add_direction(d.direction, d.stretch, 100.0,
                  {{&force, d.measured_force_N, d.simulated_force_N, 1.0, "measured", "shell model"},
                   {&comp, d.measured_compression, d.simulated_compression, 100.0, "measured", "shell model"}});
  force.attributes = attrs("fabric-shell-force", "fabric", r.id);
  comp.attributes = attrs("fabric-shell-compression", "fabric", r.id);
  h << svg::render(force);
  if (!comp.series.empty()) h << svg::render(comp);
  if (s.bending) {
    svg::XYPlot b = curve_plot("Pear loop: aspect ratio", "clamp distance [mm]", "aspect ratio [–]");
    b.y_from_zero = false;
    for (const auto& d : s.bending->curves)
      add_direction(d.direction, d.clamp_distance_m, 1e3,
                    {{&b, d.measured_aspect_ratio, d.simulated_aspect_ratio, 1.0, "measured", "shell model"}});
    b.attributes = attrs("fabric-shell-bending", "fabric", r.id);
    h << svg::render(b);
  }
}

void yarn_plots(std::ostringstream& h, const FabricRow& r) {
  const results::YarnFitFile& y = *r.outputs->yarn;
  if (y.curves.empty()) return;
  svg::XYPlot st = curve_plot("Uniform targets: stress", "stretch s [%]", "2nd Piola–Kirchhoff stress S [N/m]");
  svg::XYPlot comp = curve_plot("Uniform targets: compression", "stretch s [%]", "compression c [%]");
  for (const auto& d : y.curves) {
    const std::string& dir = d.direction;
    add_direction(dir, d.stretch, 100.0,
                  {{&st, d.target_S_N_per_m, d.simulated_S_N_per_m, 1.0, "target", "yarn model"},
                   {&comp, d.target_compression, d.simulated_compression, 100.0, "target", "yarn model"}});
    if (const auto e = y.errors_by_direction.find(dir); e != y.errors_by_direction.end()) {
      const double c = e->second.comfort_stretch;
      st.marks.push_back({100.0 * c, direction_colour(dir), dir + " end of comfort range"});
      comp.marks.push_back({100.0 * c, direction_colour(dir), ""});
    }
  }
  st.attributes = attrs("fabric-yarn-stress", "fabric", r.id);
  comp.attributes = attrs("fabric-yarn-compression", "fabric", r.id);
  h << svg::render(st) << svg::render(comp);
}

// A parameter's search range and whether it ended on it (one of `on_bound`); false when it was
// not searched.
bool searched_parameter(const std::map<std::string, results::SearchBound>& bounds,
                        const std::vector<std::string>& on_bound, const std::string& name, svg::BoundedValue& v) {
  const auto bound = bounds.find(name);
  if (bound == bounds.end()) return false;
  v.lower = bound->second.lower;
  v.upper = bound->second.upper;
  v.log = bound->second.log;
  v.on_bound = std::find(on_bound.begin(), on_bound.end(), name) != on_bound.end();
  return true;
}

// A FAB record's tests against the fitted shell model: fitted and held out apart, each against
// every loading branch, beside what the measurement itself varies (docs/fab.md).
void fab_table(std::ostringstream& h, const results::FabFitDetails& fab) {
  constexpr double gf = 9.80665e-3;  // N
  h << "<h4>FAB tests</h4><table><tr><th class=\"l\">direction</th><th class=\"l\">test</th><th class=\"l\">role</th>"
       "<th>force error, every loading branch</th><th>within the first two cycles</th><th>mean |error| [gf]</th>"
       "<th>cycles apart</th><th>hysteresis</th></tr>";
  for (const char* dir : {"weft", "bias", "warp"})
    for (const auto& t : fab.tests) {
      if (t.direction != dir) continue;
      h << "<tr><td class=\"l\">" << dir << "</td><td class=\"l\">" << escape(t.test) << "</td><td class=\"l\">"
        << (t.held_out ? "held out, predicted" : "fitted") << "</td>" << pct_cell(t.force_pct)
        << pct_cell(t.first_cycles_force_pct) << "<td>" << number_label(t.mean_abs_error_N / gf) << "</td>"
        << pct_cell(t.spread_pct) << pct_cell(t.hysteresis_pct) << "</tr>";
    }
  h << "</table><p class=\"note\">Bends are compared with each test's zero as a free offset (a loop's zero cannot "
       "be read from its data). The cycles' spread and the hysteresis are the measurement's own: an elastic model "
       "follows neither.";
  for (const auto& b : fab.bends)
    h << " k<sub>θ</sub> " << escape(b.direction) << " " << number_label(b.ktheta) << " N·m from the loop bends (misfit doubled at "
      << number_label(b.ktheta_low) << " and " << number_label(b.ktheta_high) << ")"
      << (b.on_bound ? " (at its bound)" : "") << (b.converged ? "" : " (not converged: " + escape(b.message) + ")") << ".";
  h << "</p>";
}

bool shell_parameter(const results::ShellFitFile& shell, const std::string& name, svg::BoundedValue& v) {
  return searched_parameter(shell.bounds, shell.at_bounds, name, v);
}

// The same for a yarn parameter, with how far the targets pin it (its identifiability).
bool yarn_parameter(const results::YarnFitFile& yarn, const std::string& name, svg::BoundedValue& v) {
  if (!searched_parameter(yarn.bounds, yarn.on_bound, name, v)) return false;
  if (!yarn.identifiability) return true;
  const auto e = yarn.identifiability->parameters.find(name);
  if (e != yarn.identifiability->parameters.end()) {
    v.range_refit = e->second.free ? std::numeric_limits<double>::infinity() : e->second.range_factor;
    v.range_held = e->second.range_alone_factor;
  }
  return true;
}

void parameter_plot(std::ostringstream& h, const FabricRow& r) {
  svg::BoundsPlot p;
  p.title = "Fitted parameters on their search range (log axes unless stated)";
  std::vector<std::string> fixed;
  // The shell stage's parameters first (the lock-up ones come last in k_params), then the yarn's.
  std::vector<std::size_t> order;
  for (const char* stage_name : {"shell", "yarn"})
    for (std::size_t i = 0; i < k_params.size(); ++i)
      if (std::string_view(k_params[i].stage) == stage_name) order.push_back(i);
  for (const std::size_t i : order) {
    const bool shell = std::string_view(k_params[i].stage) == "shell";
    if (!(shell ? r.has_shell() : r.has_yarn()) || !std::isfinite(r.params[i])) continue;
    const std::string name = k_params[i].key;
    svg::BoundedValue v;
    const bool searched = shell ? shell_parameter(*r.outputs->shell, name, v) : yarn_parameter(*r.outputs->yarn, name, v);
    if (!searched) {
      fixed.push_back(name + " = " + number_label(r.params[i]) + " " + k_params[i].unit);
      continue;
    }
    v.name = name;
    v.unit = k_params[i].unit;
    v.value = r.params[i];
    if (!v.log) v.name += " (linear)";
    p.values.push_back(v);
  }
  if (!p.values.empty()) {
    p.attributes = attrs("fabric-parameters", "fabric", r.id);
    h << svg::render(p);
  }
  if (!fixed.empty()) {
    h << "<p class=\"note\">Not searched (held or fixed): ";
    for (std::size_t i = 0; i < fixed.size(); ++i) h << (i ? "; " : "") << escape(fixed[i]);
    h << ".</p>";
  }
}

// "Not identified: a; b" (sorted, each once), nothing for an empty list.
void identification_note(std::ostringstream& h, const char* what, const std::vector<std::string>& items) {
  const std::set<std::string> list(items.begin(), items.end());
  if (list.empty()) return;
  h << "<p class=\"note\">" << what << ": ";
  bool first = true;
  for (const auto& s : list) h << (first ? "" : "; ") << escape(s), first = false;
  h << "</p>";
}

// "<b>scene</b>: effect, effect; …".
void list_effects(std::ostringstream& h, const std::map<std::string, std::vector<std::string>>& effects) {
  bool first = true;
  for (const auto& [scene, list] : effects) {
    h << (first ? "" : "; ") << "<b>" << escape(scene) << "</b>: ";
    for (std::size_t i = 0; i < list.size(); ++i) h << (i ? ", " : "") << escape(list[i]);
    first = false;
  }
}

// A fabric's exported files, linked relative to the page's folder.
void export_links(std::ostringstream& h, const FabricOutputs& f, const std::filesystem::path& report_dir) {
  if (f.exports.empty()) return;
  h << "<p class=\"note exports\">exports:";
  for (const auto& file : f.exports) {
    const auto absolute = std::filesystem::absolute(file).lexically_normal();
    const auto href = report_dir.empty() ? absolute : absolute.lexically_relative(std::filesystem::absolute(report_dir).lexically_normal());
    h << " <a href=\"" << escape(href.generic_string()) << "\">" << escape(file.lexically_relative(f.folder / "exports").generic_string())
      << "</a>";
  }
  h << " <span class=\"meta\">(docs/exports.md)</span></p>";
}

// "12.3 wales, 15.6 courses per 10 cm" (– for a figure the tile does not have).
std::string gauge_text(double wales, double courses) {
  const auto figure = [](double v) { return std::isfinite(v) ? number_label(v) : std::string("–"); };
  return figure(wales) + " wales, " + figure(courses) + " courses per 10 cm";
}

// The tile the yarn model was fitted on, drawn from above and from the side, with its gauge
// beside the record's (issue 48).
void tile_section(std::ostringstream& h, const FabricRow& r) {
  if (!r.outputs || !r.outputs->tile || !r.has_yarn()) return;
  const results::YarnFitFile& y = *r.outputs->yarn;
  const auto r1 = y.params.find("R1");
  const double radius = r1 != y.params.end() && r1->second > 0.0 ? r1->second : r.outputs->tile->radius;
  const TileDrawing d = draw_tile(*r.outputs->tile, radius, anchor(r.id) + "-tile", attrs("fabric-tile", "fabric", r.id));
  if (d.above.empty()) return;
  h << "<div class=\"plots tile\">" << d.above << d.side << "</div><p class=\"note\" data-tile-gauge>";
  if (y.tile) {
    const results::FittedTileRecord& t = *y.tile;
    h << "Tile fitted on (" << escape(t.source) << "): " << number_label(t.period_weft_mm) << " × "
      << number_label(t.period_warp_mm) << " mm";
    if (t.wales > 0) h << ", " << t.wales << " × " << t.courses << " stitches: " << gauge_text(t.wales_per_10cm, t.courses_per_10cm);
    else h << " (not a weft knit the count recognises: no gauge)";
    if (t.record_wales_per_10cm && t.record_courses_per_10cm)
      h << "; the record states " << gauge_text(*t.record_wales_per_10cm, *t.record_courses_per_10cm);
    else h << "; the record states no knitting_gauge";
    h << ". ";
  }
  h << "Yarns drawn at the fitted contact radius R1 = " << number_label(1e3 * radius) << " mm.</p>";
}

void fabric_section(std::ostringstream& h, const FabricRow& r, std::size_t runs, const std::filesystem::path& report_dir) {
  h << "<section class=\"fabric\" id=\"" << anchor(r.id) << "\" data-fabric=\"" << escape(r.id) << "\"><h3>"
    << escape(r.id) << " <span class=\"meta\">family " << escape(family_name(r.family))
    << (runs > 1 ? ", run " + escape(r.run) : std::string()) << ", " << escape(r.status) << "</span></h3>";
  if (!r.error.empty()) h << "<p class=\"fail\">" << escape(r.error) << "</p>";
  if (r.outputs) export_links(h, *r.outputs, report_dir);
  if (r.has_shell()) {
    // shell_fit.json names its in-plane law; outputs from before the choice existed are eq. 6.1.
    const std::string& model = r.outputs->shell->model;
    h << "<p class=\"note\" data-shell-model=\"" << escape(model) << "\">shell model: " << escape(model)
      << (model == "stiffening" ? " (eq. 6.1 with exponential lock-up per material direction and lateral shares)"
                                  : " (eq. 6.1)") << "</p>";
  }
  // The fabric's plot: its errors against the band (a row per stage).
  svg::DotPlot p;
  p.x_label = "error [%]";
  p.width = 560;
  const auto shown = [&r](std::string_view stage) {
    return stage == "shell" || (stage == "yarn" && r.has_yarn()) || (stage == "end-to-end" && r.has_end_to_end());
  };
  for (const char* stage : {"shell", "yarn", "end-to-end"}) {
    if (!shown(stage)) continue;
    for (std::size_t i : metric_indices(stage)) p.metrics.push_back(std::string(stage) + " " + k_metrics[i].label);
  }
  svg::DotRow row{r.id, "", "", {}};
  for (std::size_t i = 0; i < k_metrics.size(); ++i)
    if (shown(k_metrics[i].stage)) row.values.push_back(r.metrics[i]);
  p.rows.push_back(row);
  p.title = r.outputs && (r.has_shell() || r.has_yarn()) ? "Errors" : "No results: " + r.error;
  p.attributes = attrs("fabric", "fabric", r.id);
  h << "<div class=\"plots\">" << svg::render(p) << "</div>";
  if (!r.outputs || (!r.has_shell() && !r.has_yarn())) {
    h << "</section>";
    return;
  }
  // Errors per direction.
  h << "<table><tr><th class=\"l\">direction</th><th>shell force</th><th>shell compression</th>";
  if (r.has_yarn()) h << "<th>yarn stress, comfort</th><th>yarn stress, full</th><th>yarn compression</th><th>yarn bending</th>";
  // The fitted yarn model against the measured curves (issue 48): homogenised back to a shell
  // law and run through the record's own tests.
  if (r.has_end_to_end())
    h << "<th>end to end: force</th><th>end to end: compression</th><th>end to end: aspect ratio</th>";
  h << "</tr>";
  std::set<std::string> dirs;
  if (r.has_shell())
    for (const auto& d : r.outputs->shell->directions) dirs.insert(d.direction);
  if (r.has_yarn())
    for (const auto& [dir, e] : r.outputs->yarn->errors_by_direction) dirs.insert(dir);
  for (const char* dir : {"weft", "bias", "warp"}) {
    if (!dirs.count(dir)) continue;
    h << "<tr><td class=\"l\">" << dir << "</td>";
    const results::ShellDirectionErrors shell =
        r.has_shell() ? r.outputs->shell->direction_errors(dir) : results::ShellDirectionErrors{k_nan, k_nan, k_nan};
    h << pct_cell(shell.stretch_force_pct) << pct_cell(shell.compression_pct);
    if (r.has_yarn()) {
      const auto& by_direction = r.outputs->yarn->errors_by_direction;
      const auto e = by_direction.find(dir);
      const results::YarnDirectionErrors none = results::YarnDirectionErrors::none();
      const results::YarnDirectionErrors& y = e == by_direction.end() ? none : e->second;
      for (double v : {y.stress_comfort_pct, y.stress_full_pct, y.compression_pct, y.bending_pct.value_or(k_nan)})
        h << pct_cell(v);
    }
    if (r.has_end_to_end()) {
      const auto& by_direction = r.outputs->yarn->measured->by_direction;
      const auto e = by_direction.find(dir);
      const results::ShellDirectionErrors m =
          e == by_direction.end() ? results::ShellDirectionErrors{k_nan, k_nan, k_nan} : e->second;
      h << pct_cell(m.stretch_force_pct) << pct_cell(m.compression_pct) << pct_cell(m.bending_pct);
    }
    h << "</tr>";
  }
  h << "<tr><td class=\"l\"><b>all</b></td>";
  for (std::size_t i : metric_indices("shell", false)) h << pct_cell(r.metrics[i]);
  if (r.has_yarn())
    for (std::size_t i : metric_indices("yarn")) h << pct_cell(r.metrics[i]);
  if (r.has_end_to_end())
    for (std::size_t i : metric_indices("end-to-end")) h << pct_cell(r.metrics[i]);
  h << "</tr></table>";
  if (r.has_end_to_end() && !r.outputs->yarn->measured->ok)
    h << "<p class=\"note\">End to end: " << escape(r.outputs->yarn->measured->message) << "</p>";
  if (r.has_shell() && r.outputs->shell->fab) fab_table(h, *r.outputs->shell->fab);
  const double ar = r.metric("shell_aspect_ratio_pct");
  if (std::isfinite(ar)) h << "<p>Pear-loop aspect-ratio error " << number_label(ar) << " %.</p>";
  h << "<div class=\"plots\">";
  if (r.has_shell()) shell_plots(h, r);
  if (r.has_yarn()) yarn_plots(h, r);
  h << "</div>";
  parameter_plot(h, r);
  tile_section(h, r);
  // Identification notes.
  if (r.has_shell()) {
    identification_note(h, "Not identified", r.outputs->shell->not_identified);
    identification_note(h, "Weakly identified", r.outputs->shell->weakly_identified);
  }
  // Time per stage and the effects simulated.
  h << "<table><tr>";
  for (const auto& t : k_times) h << "<th>" << t.label << "</th>";
  h << "</tr><tr>";
  for (double t : r.times) h << "<td>" << seconds_text(t) << "</td>";
  h << "</tr></table><p class=\"note\">Effects simulated — shell: ";
  if (r.has_shell()) list_effects(h, r.outputs->shell->effects);
  if (r.has_yarn()) {
    h << "; yarn: ";
    const auto& effects = r.outputs->yarn->effects;
    for (std::size_t i = 0; i < effects.size(); ++i) h << (i ? ", " : "") << escape(effects[i]);
  }
  h << ". Files: <code>" << escape(r.outputs->folder.string()) << "</code></p></section>";
}

}  // namespace

std::string report_html(const ReportData& d, const std::string& generated, const std::filesystem::path& report_dir) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/><title>yarnfit report: " << d.fabrics.size()
    << " fabrics</title><style>" << k_css << "</style></head><body>";
  h << "<h1>yarnfit report</h1><p class=\"meta\">" << escape(generated) << " · " << d.run_summaries.size() << " run"
    << (d.run_summaries.size() == 1 ? "" : "s") << " · <a href=\"fabrics.csv\">fabrics.csv</a> · <a "
       "href=\"families.csv\">families.csv</a> · <a href=\"report.json\">report.json</a></p>";
  h << "<ul class=\"toc\"><li><a href=\"#summary\">Summary</a></li><li><a href=\"#families\">Per family</a></li>"
       "<li><a href=\"#overview\">Errors per fabric</a></li><li><a href=\"#cost\">What accuracy costs</a></li>";
  for (const auto& r : d.fabrics) h << "<li><a href=\"#" << anchor(r.id) << "\">" << escape(r.id) << "</a></li>";
  h << "</ul>";
  summary(h, d);
  family_tables(h, d);
  overview_plots(h, d);
  family_plots(h, d);
  cost_section(h, d);
  h << "<h2 id=\"fabrics\">Fabrics</h2>";
  for (const auto& r : d.fabrics) fabric_section(h, r, d.run_summaries.size(), report_dir);
  h << "</body></html>\n";
  return h.str();
}

}  // namespace yarnfit::reports
