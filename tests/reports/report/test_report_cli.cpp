// `yarnfit report` end to end (issue 19's acceptance 1 and 4). A database made here — a yarn
// record from `synth yarn` on the bundled example's tile (family soft), two shell records from
// `synth shell` (family firm; one with pear-loop tests, one without), a record alone in its
// family, and a broken record — fitted by two batches: every record, shell stage only; then the
// yarn record through the whole pipeline. The report over both:
//   - every figure equals the metric recomputed here, independently, from the curves the fits
//     wrote (shell_curves.csv, the pear-loop curves, yarn_curves.csv and uniform_targets.csv);
//   - the family statistics equal those recomputed from fabrics.csv;
//   - the broken record is failed with its reason, the lone family has no standard deviation,
//     a record without bending tests has no aspect-ratio figure and one without the yarn stage
//     no yarn figures; the yarn record is compared across the two runs;
//   - 30 fabrics in 5 families keep their rows apart.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "tests/test_support.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::testing {
namespace {

using nlohmann::json;

const fs::path k_tile = fs::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo/tile.pyp";

// A CSV file as rows of named cells.
std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::istringstream in(read_file(file));
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  const auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
      else cell += c;
    }
    cells.push_back(cell);
    return cells;
  };
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto cells = split(line);
    if (header.empty()) {
      header = cells;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

double number(const std::string& cell) { return cell.empty() ? std::nan("") : std::stod(cell); }

// 100 · Σ|sim − meas| / Σ|meas| over the rows where both are given.
double shell_metric(const std::vector<std::map<std::string, std::string>>& rows, const std::string& measured,
                    const std::string& simulated) {
  double err = 0, sum = 0;
  int n = 0;
  for (const auto& r : rows) {
    const double m = number(r.at(measured)), s = number(r.at(simulated));
    if (std::isnan(m) || std::isnan(s)) continue;
    err += std::abs(s - m);
    sum += std::abs(m);
    ++n;
  }
  return n > 0 && sum > 0 ? 100.0 * err / sum : std::nan("");
}

struct DirectionTargets {
  std::vector<double> s, stress, c;
  [[nodiscard]] double at(const std::vector<double>& v, double x) const {
    if (x <= s.front()) return v.front();
    for (std::size_t i = 1; i < s.size(); ++i)
      if (x <= s[i]) return v[i - 1] + (x - s[i - 1]) / (s[i] - s[i - 1]) * (v[i] - v[i - 1]);
    return v.back();
  }
};

// The yarn metrics (SPEC §3) of one folder, from yarn_curves.csv and the uniform targets:
// per direction the comfort range ends where the target line force first reaches 100/3 N/m;
// the stress norm is the largest PK2 target S/(1+s) up to there, the compression norm the
// largest |c| (at least 1e-3). Returns {comfort, full, compression}, each the mean over
// directions.
std::array<double, 3> yarn_metrics(const fs::path& folder) {
  std::map<std::string, DirectionTargets> targets;
  for (const auto& r : read_csv(folder / "uniform_targets.csv")) {
    if (r.at("kind") != "stretch") continue;
    auto& t = targets[r.at("direction")];
    t.s.push_back(number(r.at("stretch")));
    t.stress.push_back(number(r.at("stress_s_N_per_m")));
    t.c.push_back(number(r.at("compression")));
  }
  std::map<std::string, std::vector<std::map<std::string, std::string>>> samples;
  for (const auto& r : read_csv(folder / "yarn_curves.csv")) samples[r.at("direction")].push_back(r);
  std::array<double, 3> mean{0, 0, 0};
  for (const auto& [dir, rows] : samples) {
    const DirectionTargets& t = targets.at(dir);
    double comfort = t.s.back();
    for (std::size_t i = 1; i < t.s.size(); ++i)
      if (t.stress[i] >= 100.0 / 3.0) {
        comfort = t.s[i - 1] + (100.0 / 3.0 - t.stress[i - 1]) / (t.stress[i] - t.stress[i - 1]) * (t.s[i] - t.s[i - 1]);
        break;
      }
    double norm = t.at(t.stress, comfort) / (1 + comfort), cnorm = std::abs(t.at(t.c, comfort));
    for (std::size_t i = 0; i < t.s.size() && t.s[i] <= comfort; ++i)
      norm = std::max(norm, t.stress[i] / (1 + t.s[i])), cnorm = std::max(cnorm, std::abs(t.c[i]));
    cnorm = std::max(cnorm, 1e-3);
    double sc = 0, sf = 0, cc = 0;
    int nc = 0;
    for (const auto& r : rows) {
      const double ds = std::abs(number(r.at("simulated_S_N_per_m")) - number(r.at("target_S_N_per_m"))) / norm;
      sf += ds;
      if (number(r.at("stretch")) <= comfort + 1e-12) sc += ds, ++nc;
      cc += std::abs(number(r.at("simulated_compression")) - number(r.at("target_compression"))) / cnorm;
    }
    const double n = static_cast<double>(rows.size());
    mean[0] += 100.0 * (nc > 0 ? sc / nc : sf / n);
    mean[1] += 100.0 * sf / n;
    mean[2] += 100.0 * cc / n;
  }
  for (double& m : mean) m /= static_cast<double>(samples.size());
  return mean;
}

void expect_figure(const json& reported, double recomputed, const std::string& what) {
  if (std::isnan(recomputed)) {
    EXPECT_TRUE(reported.is_null()) << what << ": " << reported;
    return;
  }
  ASSERT_TRUE(reported.is_number()) << what << ": " << reported;
  EXPECT_NEAR(reported.get<double>(), recomputed, 1e-8 * std::max(1.0, std::abs(recomputed))) << what;
}

class ReportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_dir = std::make_unique<ScratchDir>("reportcli");
    const fs::path db = *s_dir / "db";
    fs::create_directories(db);
    db::Problems problems;
    const auto tile = db::read_pyp(k_tile, problems);
    ASSERT_TRUE(tile) << problems.to_string();
    write_file(*s_dir / "yarn.yaml",
               yarn::to_json(yarn::default_params({120.0, db::compute_tile_facts(*tile).r_est})).dump(2) + "\n");
    auto r = run_cli("synth yarn --pattern " + quoted(k_tile) + " --params " + quoted(*s_dir / "yarn.yaml") +
                     " --out " + quoted(*s_dir / "src") + " --id knit_a --family soft --max-stretch 0.15"
                     " --directions weft --points 4 -q");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    fs::copy(*s_dir / "src" / "fabric", db / "knit_a", fs::copy_options::recursive);
    const std::string bending = " --ktheta-weft 2e-6 --ktheta-bias 2.6e-6 --ktheta-warp 3.4e-6 --bending weft,warp";
    for (const auto& [id, family, extra] :
         {std::tuple{"shell_b", "firm", bending}, std::tuple{"shell_c", "firm", std::string(" --bias 0")},
          std::tuple{"solo_d", "solo", std::string(" --bias 0 --kxx 90")}}) {
      r = run_cli("synth shell --out " + quoted(db / id) + " --id " + id + " --family " + family + " --points 5" + extra);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    // The broken record: shell_c with a word for the force on line 3 of its weft curve.
    fs::copy(db / "shell_c", db / "broken_e", fs::copy_options::recursive);
    std::string yaml = read_file(db / "broken_e" / "fabric.yaml");
    yaml.replace(yaml.find("id: shell_c"), 11, "id: broken_e");
    write_file(db / "broken_e" / "fabric.yaml", yaml);
    std::string csv = read_file(db / "broken_e" / "stretch_weft.csv");
    std::size_t line3 = 0;
    for (int skip = 0; skip < 2; ++skip) line3 = csv.find('\n', line3) + 1;
    const auto comma = csv.find(',', line3);
    csv.replace(comma + 1, csv.find_first_of(",\n", comma + 1) - comma - 1, "lots");
    write_file(db / "broken_e" / "stretch_weft.csv", csv);

    r = run_cli("batch " + quoted(db) + " --out " + quoted(*s_dir / "shells") + " --stages shell --quiet --no-report");
    ASSERT_EQ(r.exit_code, 1) << r.err;
    r = run_cli("batch " + quoted(db) + " --out " + quoted(*s_dir / "yarns") + " --only knit_a --quiet"
                " --particles 3 --iterations 2 --samples 3 --local-samples 3 --local-evaluations 3 --no-profile"
                " --no-rest-shape --threads-per-job 2");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run_cli("report " + quoted(*s_dir / "shells") + " " + quoted(*s_dir / "yarns") + " --out " +
                quoted(*s_dir / "report"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    s_stdout = r.out;
  }
  static void TearDownTestSuite() { s_dir.reset(); }
  void SetUp() override { ASSERT_TRUE(s_dir && fs::exists(report() / "report.json")) << "the report was not made"; }
  static fs::path report() { return *s_dir / "report"; }
  static json report_json() { return json::parse(read_file(report() / "report.json")); }
  static std::unique_ptr<ScratchDir> s_dir;
  static std::string s_stdout;
};

std::unique_ptr<ScratchDir> ReportCli::s_dir;
std::string ReportCli::s_stdout;

void expect_files_and_where_to_open(const fs::path& dir, const fs::path& report, const std::string& out) {
  for (const char* f : {"index.html", "fabrics.csv", "families.csv", "report.json"}) EXPECT_TRUE(fs::exists(report / f)) << f;
  EXPECT_TRUE(contains(out, "report of 5 fabrics (3 families, 1 not fitted) from 2 runs: open ")) << out;
  EXPECT_TRUE(contains(out, (report / "index.html").string())) << out;
  // The yarn batch wrote its own report when it ended; the shell batch was told not to.
  EXPECT_TRUE(fs::exists(dir / "yarns" / "report" / "index.html"));
  EXPECT_FALSE(fs::exists(dir / "shells" / "report"));
}

void expect_figures_recomputed_from_the_curves(const fs::path& batches, const fs::path& report, const json& j) {
  int checked_shell = 0, checked_yarn = 0, checked_bending = 0;
  for (const auto& f : j["fabrics"]) {
    const std::string id = f["id"];
    if (f["status"] != "done") continue;
    const fs::path folder = batches / (f["run"] == "yarns" ? "yarns" : "shells") / "fabrics" / id;
    const auto curves = read_csv(folder / "shell_curves.csv");
    const auto& m = f["metrics"];
    expect_figure(m["shell_force_pct"], shell_metric(curves, "measured_force_N", "simulated_force_N"), id + " force");
    expect_figure(m["shell_compression_pct"], shell_metric(curves, "measured_compression", "simulated_compression"),
                  id + " compression");
    // Per direction too.
    for (const auto& [dir, e] : f["shell_errors_by_direction"].items()) {
      std::vector<std::map<std::string, std::string>> rows;
      for (const auto& r : curves)
        if (r.at("direction") == dir) rows.push_back(r);
      expect_figure(e["force_pct"], shell_metric(rows, "measured_force_N", "simulated_force_N"), id + " " + dir);
    }
    ++checked_shell;
    // The aspect ratio from the pear-loop curves in shell_fit.json.
    const json shell = json::parse(read_file(folder / "shell_fit.json"));
    if (shell.contains("bending")) {
      double err = 0, sum = 0;
      for (const auto& c : shell["bending"]["curves"])
        for (std::size_t i = 0; i < c["measured_aspect_ratio"].size(); ++i) {
          err += std::abs(c["simulated_aspect_ratio"][i].get<double>() - c["measured_aspect_ratio"][i].get<double>());
          sum += std::abs(c["measured_aspect_ratio"][i].get<double>());
        }
      expect_figure(m["shell_aspect_ratio_pct"], 100.0 * err / sum, id + " aspect ratio");
      ++checked_bending;
    } else {
      EXPECT_TRUE(m["shell_aspect_ratio_pct"].is_null()) << id;
    }
    if (fs::exists(folder / "yarn_fit.json")) {
      const auto y = yarn_metrics(folder);
      expect_figure(m["yarn_stress_comfort_pct"], y[0], id + " stress comfort");
      expect_figure(m["yarn_stress_full_pct"], y[1], id + " stress full");
      expect_figure(m["yarn_compression_pct"], y[2], id + " yarn compression");
      ++checked_yarn;
    } else {
      for (const char* k : {"yarn_stress_comfort_pct", "yarn_stress_full_pct", "yarn_compression_pct", "yarn_bending_pct"})
        EXPECT_TRUE(m[k].is_null()) << id << " " << k;
    }
  }
  EXPECT_EQ(checked_shell, 4);
  EXPECT_EQ(checked_yarn, 1);
  EXPECT_EQ(checked_bending, 1);

  // fabrics.csv holds the same figures; families.csv their statistics.
  std::map<std::string, std::vector<double>> force_by_family;
  for (const auto& row : read_csv(report / "fabrics.csv")) {
    for (const auto& f : j["fabrics"])
      if (f["id"] == row.at("fabric")) expect_figure(f["metrics"]["shell_force_pct"], number(row.at("shell_force_pct")), row.at("fabric") + " csv");
    if (!row.at("shell_force_pct").empty()) force_by_family[row.at("family")].push_back(number(row.at("shell_force_pct")));
  }
  const auto families = read_csv(report / "families.csv");
  ASSERT_EQ(families.size(), 3u);
  for (const auto& fam : families) {
    const auto& v = force_by_family[fam.at("family")];
    ASSERT_FALSE(v.empty()) << fam.at("family");
    double mean = 0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    EXPECT_NEAR(number(fam.at("shell_force_pct_mean")), mean, 1e-8 * mean) << fam.at("family");
    EXPECT_EQ(number(fam.at("shell_force_pct_n")), static_cast<double>(v.size()));
    EXPECT_NEAR(number(fam.at("shell_force_pct_min")), *std::min_element(v.begin(), v.end()), 1e-12);
    EXPECT_NEAR(number(fam.at("shell_force_pct_max")), *std::max_element(v.begin(), v.end()), 1e-12);
    if (v.size() >= 2) {
      double sq = 0;
      for (double x : v) sq += (x - mean) * (x - mean);
      EXPECT_NEAR(number(fam.at("shell_force_pct_sd")), std::sqrt(sq / (static_cast<double>(v.size()) - 1)), 1e-8 * mean);
    } else {
      EXPECT_TRUE(fam.at("shell_force_pct_sd").empty()) << "one fabric: no standard deviation";
    }
    int within = 0;
    for (double x : v) within += x <= 10.0;
    EXPECT_EQ(number(fam.at("shell_force_pct_within_10pct")), within);
  }
}

void expect_edge_cases(const fs::path& report, const json& j) {
  std::map<std::string, json> by_id;
  for (const auto& f : j["fabrics"]) by_id[f["id"]] = f;
  ASSERT_EQ(by_id.size(), 5u);
  const json& broken = by_id["broken_e"];
  EXPECT_EQ(broken["status"], "failed");
  ASSERT_TRUE(broken["error"].is_string());
  EXPECT_TRUE(contains(broken["error"].get<std::string>(), "stretch_weft.csv:3")) << broken["error"];
  EXPECT_TRUE(broken["metrics"]["shell_force_pct"].is_null());
  EXPECT_EQ(by_id["knit_a"]["run"], "yarns");  // the later run's row
  EXPECT_EQ(by_id["knit_a"]["stages"], "shell+yarn");
  EXPECT_EQ(by_id["shell_c"]["stages"], "shell");
  EXPECT_TRUE(by_id["shell_b"]["metrics"]["shell_aspect_ratio_pct"].is_number());
  EXPECT_TRUE(by_id["shell_c"]["metrics"]["shell_aspect_ratio_pct"].is_null());
  for (const auto& fam : j["families"])
    if (fam["family"] == "solo") {
      EXPECT_EQ(fam["fabrics"], 1);
      EXPECT_TRUE(fam["metrics"]["shell_force_pct"]["sd"].is_null());
    }
  ASSERT_EQ(j["comparison"].size(), 1u);
  EXPECT_EQ(j["comparison"][0]["fabric"], "knit_a");
  EXPECT_EQ(j["comparison"][0]["runs"].size(), 2u);
  EXPECT_EQ(j["comparison"][0]["runs"][0]["metric"], "shell_force_pct");
  EXPECT_EQ(j["comparison"][0]["runs"][1]["metric"], "yarn_stress_comfort_pct");

  const std::string html = read_file(report / "index.html");
  EXPECT_TRUE(contains(html, "stretch_weft.csv:3")) << "the failure's reason is on the page";
  EXPECT_TRUE(contains(html, "data-plot=\"cost\"")) << "two runs over knit_a: the cost plot";
  for (const auto& [id, f] : by_id)
    EXPECT_TRUE(contains(html, "data-plot=\"fabric\" data-fabric=\"" + id + "\"")) << id;
  for (const char* fam : {"soft", "firm", "solo"})
    EXPECT_TRUE(contains(html, "data-plot=\"family\" data-family=\"" + std::string(fam) + "\"")) << fam;
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg")) << "no external resource";
}

// The yarn record's tile drawn from above and from the side with its gauge (issue 48), and its
// end-to-end errors (the fitted yarn model homogenised back and run through the record's
// tests). The fixture's yarn fit is a tiny search whose model's law cannot run the record's
// clamped stretch: the page says why and the figures are empty. A copy whose check succeeded
// (its figures set here) shows them in report.json, the family table and the fabric's table.
void expect_tile_and_end_to_end(const fs::path& batches, const fs::path& report, const json& j) {
  const fs::path folder = batches / "yarns" / "fabrics" / "knit_a";
  json yarn = json::parse(read_file(folder / "yarn_fit.json"));
  ASSERT_TRUE(yarn.contains("homogenised_law"));
  const json& law = yarn.at("homogenised_law");
  ASSERT_FALSE(law.at("ok").get<bool>());
  json row = json::object();
  for (const auto& f : j.at("fabrics"))
    if (f["id"] == "knit_a") row = f;
  EXPECT_TRUE(row["metrics"]["end_to_end_force_pct"].is_null()) << row.dump();
  const std::string html = read_file(report / "index.html");
  EXPECT_TRUE(contains(html, "End to end: " + law.at("message").get<std::string>().substr(0, 40)));
  EXPECT_TRUE(contains(html, "<th>end to end: force</th>"));
  // The tile: both views of knit_a, nothing for the shell-only records.
  const std::string tile_plot = "data-plot=\"fabric-tile\" data-fabric=\"knit_a\"";
  const std::size_t first = html.find(tile_plot);
  ASSERT_NE(first, std::string::npos);
  EXPECT_NE(html.find(tile_plot, first + 1), std::string::npos) << "from above and from the side";
  EXPECT_FALSE(contains(html, "data-plot=\"fabric-tile\" data-fabric=\"shell_b\""));
  const json& t = yarn.at("tile");
  EXPECT_EQ(t.at("source"), "the record's tile file");
  // The bundled stockinette tile: one loop of one course per period.
  EXPECT_EQ(t.at("wales"), 1);
  EXPECT_EQ(t.at("courses"), 1);
  EXPECT_NEAR(t.at("wales_per_10cm").get<double>(), 100.0 / t.at("period_mm").at("weft").get<double>(), 1e-9);
  EXPECT_TRUE(contains(html, "1 × 1 stitches: ")) << "the tile's gauge under its drawing";
  EXPECT_TRUE(contains(html, "the record states no knitting_gauge"));

  // A check that succeeded, in a copy.
  ScratchDir dir("report_end_to_end");
  fs::copy(folder, dir / "knit_a", fs::copy_options::recursive);
  yarn["homogenised_law"]["ok"] = true;
  yarn["homogenised_law"]["message"] = "";
  yarn["errors_vs_measured"] = {{"all", {{"stretch_force_pct", 12.5}, {"compression_pct", 3.25}, {"bending_pct", nullptr}}},
                                {"weft", {{"stretch_force_pct", 12.5}, {"compression_pct", 3.25}, {"bending_pct", nullptr}}}};
  write_file(dir / "knit_a" / "yarn_fit.json", yarn.dump());
  write_file(dir / "knit_a" / "tile.pyp", "*pattern\nnot a tile\n");  // a broken tile is left out, and said
  const auto r = run_cli("report " + quoted(dir / "knit_a") + " --out " + quoted(dir / "report") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json copy = json::parse(read_file(dir / "report" / "report.json"));
  const json& m = copy.at("fabrics").at(0).at("metrics");
  EXPECT_DOUBLE_EQ(m.at("end_to_end_force_pct").get<double>(), 12.5);
  EXPECT_DOUBLE_EQ(m.at("end_to_end_compression_pct").get<double>(), 3.25);
  EXPECT_TRUE(m.at("end_to_end_aspect_ratio_pct").is_null());
  const std::string page = read_file(dir / "report" / "index.html");
  EXPECT_TRUE(contains(page, "data-plot=\"overview\" data-stage=\"end-to-end\""));
  EXPECT_FALSE(contains(page, "data-plot=\"fabric-tile\""));
  EXPECT_TRUE(contains(page, "tile.pyp")) << "the broken tile named";
  EXPECT_TRUE(contains(page, "(the tile is not drawn)"));
  EXPECT_TRUE(contains(page, "<td class=\"l\">end-to-end</td><td class=\"l\">force</td>")) << "the family table";
}

// One report made once (a fixture runs two batches): its files, its figures against the curves,
// and the edge cases.
TEST_F(ReportCli, OverTwoBatchesEqualsTheCurvesAndHandlesTheEdgeCases) {
  {
    SCOPED_TRACE("files and the line saying where to open the report");
    expect_files_and_where_to_open(s_dir->path(), report(), s_stdout);
  }
  const json j = report_json();
  {
    SCOPED_TRACE("figures recomputed from the curves");
    expect_figures_recomputed_from_the_curves(s_dir->path(), report(), j);
  }
  {
    SCOPED_TRACE("edge cases");
    expect_edge_cases(report(), j);
  }
  {
    SCOPED_TRACE("the tile drawn and the end-to-end errors");
    expect_tile_and_end_to_end(s_dir->path(), report(), j);
  }
}

// 30 fabrics in 5 families: copies of one fit's outputs under other ids and families. Rows of
// every dot plot stay at least a text line apart and no two labels of a plot share a line.
TEST(ReportLayout, ThirtyFabricsInFiveFamiliesKeepTheirRowsApart) {
  ScratchDir dir("reportlayout");
  auto fit = run_cli("synth shell --out " + quoted(dir / "rec") + " --id one --points 5 --bias 0");
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  fit = run_cli("shell fit " + quoted(dir / "rec") + " --out " + quoted(dir / "fit") + " --quiet");
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  const fs::path many = dir / "many";
  const json shell = json::parse(read_file(dir / "fit" / "shell_fit.json"));
  for (int k = 0; k < 30; ++k) {
    const std::string id = "fabric_with_a_long_name_" + std::to_string(k);
    json s = shell;
    s["fabric"] = id;
    s["family"] = "family_" + std::to_string(k % 5);
    s["errors"]["stretch_force_pct"] = 0.7 * k;
    fs::create_directories(many / id);
    write_file(many / id / "shell_fit.json", s.dump());
  }
  const auto r = run_cli("report " + quoted(many) + " --out " + quoted(dir / "many_report") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = read_file(dir / "many_report" / "index.html");
  // The plots are cut out by plain search: libstdc++'s regex matches (.*?) by recursion, one
  // frame a character, and a plot of thirty rows overflowed the stack under ASan.
  const std::regex label_re("<text x=\"([0-9.]+)\" y=\"([0-9.]+)\" text-anchor=\"end\" class=\"row-label\">");
  std::vector<std::string> bodies;
  for (std::size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1)) {
    const std::size_t open_end = html.find('>', at);
    const std::size_t close = html.find("</svg>", at);
    ASSERT_NE(close, std::string::npos);
    const std::string open = html.substr(at, open_end - at);
    if (contains(open, "data-plot=\"overview\"") || contains(open, "data-plot=\"family\""))
      bodies.push_back(html.substr(open_end + 1, close - open_end - 1));
  }
  int plots = 0;
  for (const std::string& body : bodies) {
    std::vector<double> ys;
    for (auto l = std::sregex_iterator(body.begin(), body.end(), label_re); l != std::sregex_iterator(); ++l)
      ys.push_back(std::stod((*l)[2]));
    std::sort(ys.begin(), ys.end());
    for (std::size_t i = 1; i < ys.size(); ++i) EXPECT_GE(ys[i] - ys[i - 1], 14.0) << "plot " << plots;
    ++plots;
  }
  EXPECT_EQ(plots, 1 + 5);  // the overview (shell only) and one per family
}

}  // namespace
}  // namespace yarnfit::testing
