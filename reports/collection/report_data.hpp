#pragma once
// The numbers of a report (index.html, fabrics.csv, families.csv and report.json all show
// these): one row per fabric, the statistics per family (Table 6.1 of the thesis), and the
// runs with what their accuracy cost in time.
//
// Every figure is read from the fits' result files as they wrote them (SPEC §3 error metrics,
// results/ types), the per-direction ones included; nothing is recomputed here, so the report
// says what the fits said. A test recomputes them from the curves
// (tests/reports/report/test_report_cli.cpp).
//
// When several runs hold the same fabric, the fabric's row is its *last* run's (runs in the
// order given): the families and the per-fabric sections show that one, and the comparison
// shows all of them.

#include <array>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/collection/fit_outputs.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::reports {

using numerics::k_nan;
inline constexpr double k_good_fit_pct = 10.0;  // the thesis's "within 10 %" (Fig. 6.15)

struct MetricInfo {
  const char* key;        // report.json / CSV name
  const char* stage;      // shell, yarn or end-to-end
  const char* label;      // what the page calls it
  double results::ShellErrors::*shell_error = nullptr;  // the figure of the stage's errors
  double results::YarnErrors::*yarn_error = nullptr;
  // end-to-end: the fitted yarn model against the measured curves (yarn_fit.json's
  // errors_vs_measured, issue 48), in the shell fit's metric.
  double results::ShellErrors::*measured_error = nullptr;
};
inline constexpr std::array<MetricInfo, 10> k_metrics{{
    {"shell_force_pct", "shell", "force", &results::ShellErrors::stretch_force_pct, nullptr},
    {"shell_compression_pct", "shell", "compression", &results::ShellErrors::compression_pct, nullptr},
    {"shell_aspect_ratio_pct", "shell", "aspect ratio", &results::ShellErrors::bending_pct, nullptr},
    {"yarn_stress_comfort_pct", "yarn", "stress, comfort range", nullptr, &results::YarnErrors::stress_comfort_pct},
    {"yarn_stress_full_pct", "yarn", "stress, full range", nullptr, &results::YarnErrors::stress_full_pct},
    {"yarn_compression_pct", "yarn", "compression", nullptr, &results::YarnErrors::compression_pct},
    {"yarn_bending_pct", "yarn", "bending", nullptr, &results::YarnErrors::bending_pct},
    {"end_to_end_force_pct", "end-to-end", "force", nullptr, nullptr, &results::ShellErrors::stretch_force_pct},
    {"end_to_end_compression_pct", "end-to-end", "compression", nullptr, nullptr, &results::ShellErrors::compression_pct},
    {"end_to_end_aspect_ratio_pct", "end-to-end", "aspect ratio", nullptr, nullptr, &results::ShellErrors::bending_pct},
}};

struct ParamInfo {
  const char* key;
  const char* stage;
  const char* unit;
};
// The stiffening shell law's lock-up parameters come last (columns added after the others;
// empty for a thesis-law fit).
inline constexpr std::array<ParamInfo, 25> k_params{{
    {"kxx", "shell", "N/m"}, {"kxy", "shell", "N/m"}, {"kyy", "shell", "N/m"}, {"kss", "shell", "N/m"},
    {"kn1", "shell", "N/m"}, {"kn2", "shell", "N/m"}, {"ktheta_weft", "shell", "N·m"},
    {"ktheta_bias", "shell", "N·m"}, {"ktheta_warp", "shell", "N·m"}, {"ks1", "yarn", "N"},
    {"eps_s", "yarn", ""}, {"kb", "yarn", "N·m²"}, {"R1", "yarn", "m"}, {"kc1", "yarn", "N/m"},
    {"ks2", "yarn", "N"}, {"kc2", "yarn", "N/m"}, {"R2", "yarn", "m"},
    {"lxx", "shell", "N/m"}, {"bxx", "shell", ""}, {"lyy", "shell", "N/m"}, {"byy", "shell", ""},
    {"lss", "shell", "N/m"}, {"bss", "shell", ""}, {"axx", "shell", ""}, {"ayy", "shell", ""},
}};

struct TimeInfo {
  const char* key;
  const char* label;
};
inline constexpr std::array<TimeInfo, 7> k_times{{
    {"shell_inplane_s", "shell in-plane"},
    {"shell_bending_s", "shell bending"},
    {"yarn_swarm_s", "yarn swarm"},
    {"yarn_local_s", "yarn local step"},
    {"yarn_bending_check_s", "yarn bending check"},
    {"yarn_profile_s", "yarn identifiability"},
    {"total_s", "total"},
}};

// Positions in k_metrics and k_times by name (the size of the list for an unknown name).
constexpr std::size_t metric_index(std::string_view key) {
  for (std::size_t i = 0; i < k_metrics.size(); ++i)
    if (key == k_metrics[i].key) return i;
  return k_metrics.size();
}
constexpr std::size_t time_index(std::string_view key) {
  for (std::size_t i = 0; i < k_times.size(); ++i)
    if (key == k_times[i].key) return i;
  return k_times.size();
}

struct FabricRow {
  std::string id;
  std::string family;
  std::string run;  // label of the run it comes from
  int run_index = 0;
  std::string status;
  std::string error;
  const FabricOutputs* outputs = nullptr;  // its files (owned by the runs)
  std::array<double, k_metrics.size()> metrics;
  std::array<double, k_params.size()> params;
  std::array<double, k_times.size()> times;
  FabricRow() { metrics.fill(k_nan), params.fill(k_nan), times.fill(k_nan); }
  [[nodiscard]] double metric(std::string_view key) const { return metrics.at(metric_index(key)); }
  [[nodiscard]] double total_seconds() const { return times.at(time_index("total_s")); }
  [[nodiscard]] bool has_shell() const { return outputs && outputs->shell.has_value(); }
  [[nodiscard]] bool has_yarn() const { return outputs && outputs->yarn.has_value(); }
  [[nodiscard]] bool has_end_to_end() const { return has_yarn() && outputs->yarn->measured.has_value(); }
  // The figure the run comparison ranks by: the yarn comfort-range stress error when the yarn
  // stage ran, else the shell force error.
  [[nodiscard]] double headline_pct() const;
  [[nodiscard]] const char* headline_key() const;
};

struct MetricStats {
  int n = 0;  // fabrics with a figure
  double mean = k_nan, sd = k_nan, min = k_nan, max = k_nan;  // sd over n − 1; NaN for n < 2
  int within = 0;  // figures ≤ 10 %
};

struct FamilyStats {
  std::string family;
  int fabrics = 0;
  int failed = 0;
  std::array<MetricStats, k_metrics.size()> metrics;
};

struct RunSummary {
  std::string label;
  std::string source;
  int fabrics = 0, done = 0, failed = 0;
  double seconds = 0.0;  // total fit time of its fabrics
};

struct ReportData {
  ReportData() = default;
  ReportData(ReportData&&) = default;
  ReportData& operator=(ReportData&&) = default;
  ReportData(const ReportData&) = delete;  // the rows point into `runs`
  ReportData& operator=(const ReportData&) = delete;

  std::vector<RunOutputs> runs;
  std::vector<RunSummary> run_summaries;
  std::vector<FabricRow> fabrics;  // one per fabric id, family then id order
  std::vector<FamilyStats> families;  // name order ("" last, shown as "(no family)")
  // Every (run, fabric) pair, for the comparison: fabric id → rows in run order.
  std::map<std::string, std::vector<FabricRow>> by_run;
  std::vector<std::string> problems;
  [[nodiscard]] bool has_yarn() const;
  [[nodiscard]] bool has_bending() const;
  [[nodiscard]] bool has_end_to_end() const;
};

// The rows of one fabric's outputs in a run.
FabricRow fabric_row(const FabricOutputs& f, const std::string& run, int run_index);
// Statistics of the figures (NaN skipped).
MetricStats metric_stats(const std::vector<double>& values);
// Everything, from the runs in the order given (later runs replace earlier rows of a fabric).
ReportData make_report_data(std::vector<RunOutputs> runs);

// The three machine-readable files.
nlohmann::json report_json(const ReportData& data);
std::string fabrics_csv(const ReportData& data);
std::string families_csv(const ReportData& data);

// "(no family)" for records without one.
std::string family_name(const std::string& family);

}  // namespace yarnfit::reports
