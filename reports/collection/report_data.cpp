#include "reports/collection/report_data.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "numerics/util/format.hpp"
#include "results/metrics/error_metrics.hpp"

namespace yarnfit::reports {

using nlohmann::json;
using results::number_or_nan;
using results::pct_json;

namespace {

// A CSV cell: the number with 10 significant digits, or empty for no figure.
std::string cell(double v) {
  if (!std::isfinite(v)) return "";
  return numerics::format_number(v, 10);
}

std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c == '\n' ? ' ' : c;
  }
  return out + "\"";
}

json stats_json(const MetricStats& s) {
  return {{"n", s.n},     {"mean", pct_json(s.mean)}, {"sd", pct_json(s.sd)},
          {"min", pct_json(s.min)}, {"max", pct_json(s.max)}, {"within_10pct", s.within}};
}

}  // namespace

std::string family_name(const std::string& family) { return family.empty() ? "(no family)" : family; }

double FabricRow::headline_pct() const {
  return metric(headline_key());
}

const char* FabricRow::headline_key() const { return has_yarn() ? "yarn_stress_comfort_pct" : "shell_force_pct"; }

FabricRow fabric_row(const FabricOutputs& f, const std::string& run, int run_index) {
  FabricRow r;
  r.id = f.id;
  r.family = f.family;
  r.run = run;
  r.run_index = run_index;
  r.status = f.status;
  r.error = f.error;
  r.outputs = &f;
  for (std::size_t i = 0; i < k_metrics.size(); ++i) {
    if (f.shell && k_metrics[i].shell_error) r.metrics[i] = f.shell->errors.*k_metrics[i].shell_error;
    if (f.yarn && k_metrics[i].yarn_error) r.metrics[i] = f.yarn->errors.*k_metrics[i].yarn_error;
    if (f.yarn && f.yarn->measured && k_metrics[i].measured_error)
      r.metrics[i] = f.yarn->measured->all.*k_metrics[i].measured_error;
  }
  for (std::size_t i = 0; i < k_params.size(); ++i) {
    if (std::string_view(k_params[i].stage) == "shell") {
      if (!f.shell) continue;
      const auto p = f.shell->params.find(k_params[i].key);
      if (p != f.shell->params.end() && p->second) r.params[i] = *p->second;
    } else if (f.yarn) {
      const auto p = f.yarn->params.find(k_params[i].key);
      if (p != f.yarn->params.end()) r.params[i] = p->second;
    }
  }
  double total = 0.0;
  bool any = false;
  if (f.shell) {
    r.times[time_index("shell_inplane_s")] = f.shell->inplane ? f.shell->inplane->timing_s : f.shell->timing_s;
    if (f.shell->bending) r.times[time_index("shell_bending_s")] = f.shell->bending->timing_s;
    const double t = f.shell->timing_s;
    if (std::isfinite(t)) total += t, any = true;
  }
  if (f.yarn) {
    const results::YarnTiming& t = f.yarn->timing_s;
    r.times[time_index("yarn_swarm_s")] = t.swarm;
    r.times[time_index("yarn_local_s")] = t.local;
    r.times[time_index("yarn_bending_check_s")] = t.bending_check;
    r.times[time_index("yarn_profile_s")] = t.profile;
    const double yt = t.total;
    if (std::isfinite(yt)) total += yt, any = true;
  }
  r.times[time_index("total_s")] = any ? total : k_nan;
  return r;
}

MetricStats metric_stats(const std::vector<double>& values) {
  MetricStats s;
  double sum = 0.0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    ++s.n;
    sum += v;
    s.min = s.n == 1 ? v : std::min(s.min, v);
    s.max = s.n == 1 ? v : std::max(s.max, v);
    if (v <= k_good_fit_pct) ++s.within;
  }
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  if (s.n >= 2) {
    double sq = 0.0;
    for (double v : values)
      if (std::isfinite(v)) sq += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(sq / (s.n - 1));
  }
  return s;
}

bool ReportData::has_yarn() const {
  return std::any_of(fabrics.begin(), fabrics.end(), [](const FabricRow& r) { return r.has_yarn(); });
}

bool ReportData::has_end_to_end() const {
  return std::any_of(fabrics.begin(), fabrics.end(), [](const FabricRow& r) { return r.has_end_to_end(); });
}

bool ReportData::has_bending() const {
  return std::any_of(fabrics.begin(), fabrics.end(),
                     [](const FabricRow& r) { return std::isfinite(r.metric("shell_aspect_ratio_pct")); });
}

ReportData make_report_data(std::vector<RunOutputs> runs) {
  ReportData data;
  data.runs = std::move(runs);
  std::map<std::string, FabricRow> latest;
  for (std::size_t k = 0; k < data.runs.size(); ++k) {
    const RunOutputs& run = data.runs[k];
    RunSummary s;
    s.label = run.label;
    s.source = run.source.string();
    for (const auto& p : run.problems) data.problems.push_back(p);
    for (const auto& f : run.fabrics) {
      FabricRow row = fabric_row(f, run.label, static_cast<int>(k));
      ++s.fabrics;
      if (row.status == "done") ++s.done;
      if (row.status == "failed") ++s.failed;
      if (std::isfinite(row.total_seconds())) s.seconds += row.total_seconds();
      data.by_run[row.id].push_back(row);
      latest[row.id] = row;
    }
    data.run_summaries.push_back(s);
  }
  for (auto& [id, row] : latest) data.fabrics.push_back(row);
  std::stable_sort(data.fabrics.begin(), data.fabrics.end(), [](const FabricRow& a, const FabricRow& b) {
    if (a.family.empty() != b.family.empty()) return b.family.empty();
    return a.family < b.family;
  });
  for (const auto& row : data.fabrics) {
    if (data.families.empty() || data.families.back().family != row.family) {
      FamilyStats fam;
      fam.family = row.family;
      data.families.push_back(fam);
    }
    FamilyStats& fam = data.families.back();
    ++fam.fabrics;
    if (row.status == "failed") ++fam.failed;
  }
  for (auto& fam : data.families) {
    for (std::size_t i = 0; i < k_metrics.size(); ++i) {
      std::vector<double> v;
      for (const auto& row : data.fabrics)
        if (row.family == fam.family) v.push_back(row.metrics[i]);
      fam.metrics[i] = metric_stats(v);
    }
  }
  return data;
}

json report_json(const ReportData& data) {
  json j;
  j["version"] = 1;
  j["good_fit_pct"] = k_good_fit_pct;
  json runs = json::array();
  for (const auto& r : data.run_summaries)
    runs.push_back({{"label", r.label}, {"source", r.source}, {"fabrics", r.fabrics}, {"done", r.done},
                    {"failed", r.failed}, {"seconds", r.seconds}});
  j["runs"] = runs;
  const auto row_json = [](const FabricRow& r) {
    json m = json::object(), p = json::object(), t = json::object();
    for (std::size_t i = 0; i < k_metrics.size(); ++i) m[k_metrics[i].key] = pct_json(r.metrics[i]);
    for (std::size_t i = 0; i < k_params.size(); ++i) p[k_params[i].key] = pct_json(r.params[i]);
    for (std::size_t i = 0; i < k_times.size(); ++i) t[k_times[i].key] = pct_json(r.times[i]);
    json row = {{"id", r.id},         {"family", r.family}, {"run", r.run}, {"status", r.status},
                {"error", r.error.empty() ? json() : json(r.error)}, {"stages", r.has_yarn() ? "shell+yarn" : "shell"},
                {"metrics", m},       {"params", p},        {"times_s", t}};
    if (r.has_yarn()) row["yarn_errors_by_direction"] = results::direction_errors_json(r.outputs->yarn->errors_by_direction);
    if (r.has_shell()) {
      json dirs = json::object();
      for (const auto& d : r.outputs->shell->directions) {
        const results::ShellDirectionErrors e = r.outputs->shell->direction_errors(d.direction);
        dirs[d.direction] = {{"force_pct", pct_json(e.stretch_force_pct)}, {"compression_pct", pct_json(e.compression_pct)}};
      }
      row["shell_errors_by_direction"] = dirs;
    }
    return row;
  };
  json fabrics = json::array();
  for (const auto& r : data.fabrics) fabrics.push_back(row_json(r));
  j["fabrics"] = fabrics;
  json families = json::array();
  for (const auto& f : data.families) {
    json m = json::object();
    for (std::size_t i = 0; i < k_metrics.size(); ++i) m[k_metrics[i].key] = stats_json(f.metrics[i]);
    families.push_back({{"family", f.family}, {"fabrics", f.fabrics}, {"failed", f.failed}, {"metrics", m}});
  }
  j["families"] = families;
  json comparison = json::array();
  for (const auto& [id, rows] : data.by_run) {
    if (rows.size() < 2) continue;
    json entries = json::array();
    for (const auto& r : rows)
      entries.push_back({{"run", r.run}, {"metric", r.headline_key()}, {"error_pct", pct_json(r.headline_pct())},
                         {"seconds", pct_json(r.total_seconds())}});
    comparison.push_back({{"fabric", id}, {"runs", entries}});
  }
  j["comparison"] = comparison;
  j["problems"] = data.problems;
  return j;
}

std::string fabrics_csv(const ReportData& data) {
  std::ostringstream out;
  out << "fabric,family,run,status,stages";
  for (const auto& m : k_metrics) out << "," << m.key;
  for (const auto& p : k_params) out << "," << p.key;
  for (const auto& t : k_times) out << "," << t.key;
  out << ",error\n";
  for (const auto& r : data.fabrics) {
    out << csv_text(r.id) << "," << csv_text(r.family) << "," << csv_text(r.run) << "," << r.status << ","
        << (r.has_yarn() ? "shell+yarn" : "shell");
    for (double v : r.metrics) out << "," << cell(v);
    for (double v : r.params) out << "," << cell(v);
    for (double v : r.times) out << "," << cell(v);
    out << "," << csv_text(r.error) << "\n";
  }
  return out.str();
}

std::string families_csv(const ReportData& data) {
  std::ostringstream out;
  out << "family,fabrics,failed";
  for (const auto& m : k_metrics)
    for (const char* s : {"n", "mean", "sd", "min", "max", "within_10pct"}) out << "," << m.key << "_" << s;
  out << "\n";
  for (const auto& f : data.families) {
    out << csv_text(f.family) << "," << f.fabrics << "," << f.failed;
    for (const auto& s : f.metrics)
      out << "," << s.n << "," << cell(s.mean) << "," << cell(s.sd) << "," << cell(s.min) << "," << cell(s.max) << ","
          << s.within;
    out << "\n";
  }
  return out.str();
}

}  // namespace yarnfit::reports
