// Generated knit tiles (issue 20), printed, not asserted:
//   matrix   every named chart at the four acrylic stitch lengths and radii and at R = 0.1 and
//            1 mm (L = 11.28 mm): relaxed or why not, rest stress against σ_s(10 %), spacings,
//            time (acceptance 2)
//   hylc     a stockinette generated at the shared HYLC stockinette's yarn length per stitch
//            and radius against that tile: course and wale spacing, and free-compression
//            stretch curves 0–40 % in weft and warp with the same yarn parameters, both after
//            the rest-shape heuristic the fit applies (acceptance 3; goals: spacings within
//            10 %, curves within 20 %)
//   ratios   extensibility of the acrylic knits: the 1×1 rib across against along the wales,
//            garter against stockinette along the wales, simulated (σ_s at 10 % stretch of the
//            generated tiles, same yarn parameters per radius) beside the measured line forces
//            at 10 % stretch (../shared/data/measured/stitch-by-stitch) (acceptance 4)
// Usage: bench_tiles [matrix|hylc|ratios|all] [SHARED_DIR]
// Yarn parameters: SPEC §3's defaults with R_est = R and ks2 = 400 N.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/generate/knit_generation.hpp"
#include "yarn_fit/homogenise/rest_shape.hpp"
#include "yarn_fit/periodic/yarn_tile.hpp"
#include "yarn_fit/scenes/stretch_sweep.hpp"

namespace {

using namespace yarnfit;
using namespace yarnfit::yarn;

struct Knit {
  const char* chart;
  const char* measured;  // stem in stitch-by-stitch/acrylic
  double stitch_length_mm, radius_mm;
};
const std::vector<Knit> kAcrylic{{"stockinette", "stockinette", 11.28, 0.74},
                                 {"garter", "garter", 10.55, 0.54},
                                 {"rib1x1", "rib", 16.10, 1.18},
                                 {"seed", "seed", 15.67, 1.20}};

GeneratedTile generate(const std::string& chart, double stitch_length_mm, double radius_mm) {
  TileGenerationOptions o;
  o.geometry.stitch_length = 1e-3 * stitch_length_mm;
  o.geometry.yarn_radius = 1e-3 * radius_mm;
  return generate_knit_tile(*db::parse_knit_chart(chart), o);
}

void matrix() {
  std::printf("relaxation of every named chart (goal: rest stress <= 1 %% of sigma_s(10 %%) in weft and warp)\n");
  std::printf("  %-11s %6s %5s  %-9s %9s %9s %9s  %6s  %s\n", "chart", "L mm", "R mm", "relaxed", "rest/s10",
              "wales mm", "courses", "s", "why not");
  int relaxed = 0, total = 0;
  for (const auto& chart : db::named_knit_charts()) {
    std::vector<std::pair<double, double>> scales;
    for (const Knit& k : kAcrylic) scales.emplace_back(k.stitch_length_mm, k.radius_mm);
    scales.emplace_back(11.28, 0.1);
    scales.emplace_back(11.28, 1.0);
    for (const auto& [length, radius] : scales) {
      ++total;
      try {
        const GeneratedTile t = generate(chart, length, radius);
        relaxed += t.converged ? 1 : 0;
        std::printf("  %-11s %6.2f %5.2f  %-9s %8.3f%% %9.3f %9.3f  %6.2f  %s\n", chart.c_str(), length, radius,
                    t.converged ? "yes" : "NO", 100.0 * t.rest_stress_ratio, 1e3 * t.wale_spacing(),
                    1e3 * t.course_spacing(), t.seconds, t.message.c_str());
      } catch (const std::exception& e) {
        std::printf("  %-11s %6.2f %5.2f  %-9s %s\n", chart.c_str(), length, radius, "refused", e.what());
      }
      std::fflush(stdout);
    }
  }
  std::printf("  relaxed %d of %d   goal: all   %s\n", relaxed, total, relaxed == total ? "met" : "MISSED");
}

// Yarn length per stitch of a stockinette tile with one loop per stitch: rest length over loops
// (y maxima along the first yarn times the number of yarns).
double stitch_count(const db::PeriodicTile& tile, const db::TileFacts& facts) {
  const auto& first = facts.yarns.front();
  int peaks = 0;
  const int n = static_cast<int>(first.edges.size());
  const auto y = [&](int i) { return tile.positions[static_cast<std::size_t>(tile.edges[static_cast<std::size_t>(first.edges[static_cast<std::size_t>((i + n) % n)])].v0)][1]; };
  for (int i = 0; i < n; ++i) peaks += (y(i) > y(i - 1) && y(i) >= y(i + 1)) ? 1 : 0;
  return static_cast<double>(peaks * static_cast<int>(facts.yarns.size()));
}

std::vector<double> curve(const db::PeriodicTile& pyp, const YarnParams& params, double angle,
                          const std::vector<double>& stretches, double& rest_seconds) {
  YarnSystem system(make_yarn_tile(pyp), params);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(system.dof_count());
  const RestShapeResult rest = relax_rest_shape(system, g);
  rest_seconds = rest.seconds;
  const StretchSweep sweep = sweep_stretch(system, angle, stretches, g);
  std::vector<double> out;
  for (const Sample& s : sweep.points) out.push_back(s.ok ? s.stress_s : std::nan(""));
  return out;
}

void hylc(const std::string& shared) {
  db::Problems problems;
  const auto tile = db::read_pyp(shared + "/data/patterns/stockinette.pyp", problems);
  if (!tile) throw std::runtime_error(problems.to_string());
  const db::TileFacts facts = db::compute_tile_facts(*tile);
  const double stitches = stitch_count(*tile, facts);
  const double length = facts.total_rest_length / stitches;
  const int per_course = static_cast<int>(std::lround(stitches / static_cast<double>(facts.yarns.size())));
  const double wales = tile->period_x / per_course;
  const double courses = tile->period_y / static_cast<double>(facts.yarns.size());
  std::printf("shared HYLC stockinette: %g stitches (%d per course), yarn length per stitch %.3f mm, radius %.3f mm, "
              "wales %.3f mm and courses %.3f mm apart\n",
              stitches, per_course, 1e3 * length, 1e3 * tile->radius, 1e3 * wales, 1e3 * courses);
  const GeneratedTile t = generate("stockinette", 1e3 * length, 1e3 * tile->radius);
  std::printf("generated stockinette at the same L and R: %s in %.2f s, wales %.3f mm (%+.1f %%), courses %.3f mm "
              "(%+.1f %%)   goal: within 10 %%   %s\n",
              t.converged ? "relaxed" : ("NOT relaxed: " + t.message).c_str(), t.seconds, 1e3 * t.wale_spacing(),
              100.0 * (t.wale_spacing() / wales - 1.0), 1e3 * t.course_spacing(),
              100.0 * (t.course_spacing() / courses - 1.0),
              std::abs(t.wale_spacing() / wales - 1.0) <= 0.1 && std::abs(t.course_spacing() / courses - 1.0) <= 0.1
                  ? "met"
                  : "MISSED");
  const YarnParams params = default_params({400.0, tile->radius});
  const std::vector<double> stretches = even_stretches(0.4, 9);
  for (const auto& [angle, name] : {std::pair{weft_angle(), "weft"}, {warp_angle(), "warp"}}) {
    double rest_shared = 0.0, rest_generated = 0.0;
    const auto shared_curve = curve(*tile, params, angle, stretches, rest_shared);
    const auto generated_curve = curve(t.tile, params, angle, stretches, rest_generated);
    double worst = 0.0;
    std::printf("  %s, sigma_s [N/m] (rest shapes %.1f s / %.1f s):\n    stretch  shared  generated  difference\n",
                name, rest_shared, rest_generated);
    for (std::size_t i = 0; i < stretches.size(); ++i) {
      const double diff = (generated_curve[i] - shared_curve[i]) / std::max(std::abs(shared_curve.back()), 1e-300);
      if (i > 0) worst = std::max(worst, std::abs(diff));
      std::printf("    %5.2f  %8.4g  %8.4g  %+7.1f %% of the shared tile's stress at 40 %%\n", stretches[i],
                  shared_curve[i], generated_curve[i], 100.0 * diff);
    }
    std::printf("  %s curve: largest difference %.1f %% of the stress at 40 %%   goal: within 20 %%   %s\n", name,
                100.0 * worst, worst <= 0.2 ? "met" : "MISSED");
  }
}

// Measured line force [N/m] at stretch s of acrylic/<stem>_<dir>: the merged curve's force,
// interpolated, over the fabric width at the clamp.
double measured_line_force(const std::string& shared, const std::string& stem, const char* dir, double s) {
  const std::string base = shared + "/data/measured/stitch-by-stitch/acrylic/" + stem + "_" + dir;
  db::Problems problems;
  const auto table = db::read_csv(base + "_merged.csv", {}, problems);
  if (!table) throw std::runtime_error(problems.to_string());
  const int cs = *table->column("stretch"), cf = *table->column("force_N");
  std::vector<std::pair<double, double>> points;
  for (const auto& row : table->rows)
    if (!row.cells[static_cast<std::size_t>(cf)].empty())
      points.emplace_back(std::stod(row.cells[static_cast<std::size_t>(cs)]), std::stod(row.cells[static_cast<std::size_t>(cf)]));
  double force = std::nan("");
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i - 1].first <= s && s <= points[i].first)
      force = points[i - 1].second + (points[i].second - points[i - 1].second) * (s - points[i - 1].first) /
                                         (points[i].first - points[i - 1].first);
  const YAML::Node yaml = YAML::LoadFile(base + ".yaml");
  return force / (1e-3 * yaml["gauge"]["fabric_width_at_clamp_mm"].as<double>());
}

void ratios(const std::string& shared) {
  std::printf("extensibility at 10 %% stretch: line stress along one direction over the other (higher = the "
              "second direction stretches more easily)\n");
  std::vector<GeneratedTile> tiles;
  for (const Knit& k : kAcrylic) tiles.push_back(generate(k.chart, k.stitch_length_mm, k.radius_mm));
  for (std::size_t i = 0; i < kAcrylic.size(); ++i) {
    const Knit& k = kAcrylic[i];
    const double x = measured_line_force(shared, k.measured, "x", 0.1), y = measured_line_force(shared, k.measured, "y", 0.1);
    std::printf("  %-11s measured (X, Y) = (%.3g, %.3g) N/m, simulated (weft, warp) = (%.4g, %.4g) N/m%s\n", k.chart, x, y,
                tiles[i].stress_at_10[0], tiles[i].stress_at_10[1], tiles[i].converged ? "" : " (NOT relaxed)");
  }
  const auto line = [&](const char* what, double measured, double simulated) {
    std::printf("  %-58s measured %6.2f   simulated %6.2f   %s\n", what, measured, simulated,
                (measured > 1.0) == (simulated > 1.0) ? "same sense" : "OPPOSITE");
  };
  const double rib_x = measured_line_force(shared, "rib", "x", 0.1), rib_y = measured_line_force(shared, "rib", "y", 0.1);
  line("1x1 rib: along the wales (Y) over across them (X)", rib_y / rib_x, tiles[2].stress_at_10[1] / tiles[2].stress_at_10[0]);
  const double st_y = measured_line_force(shared, "stockinette", "y", 0.1), ga_y = measured_line_force(shared, "garter", "y", 0.1);
  line("along the wales (Y): stockinette over garter", st_y / ga_y, tiles[0].stress_at_10[1] / tiles[1].stress_at_10[1]);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "all";
  const std::string shared = argc > 2 ? argv[2] : YARNFIT_SHARED_DIR;
  if (mode != "matrix" && mode != "hylc" && mode != "ratios" && mode != "all") {
    std::fprintf(stderr, "usage: bench_tiles [matrix|hylc|ratios|all] [SHARED_DIR]\n");
    return 2;
  }
  try {
    if (mode == "matrix" || mode == "all") matrix();
    if (mode == "hylc" || mode == "all") hylc(shared);
    if (mode == "ratios" || mode == "all") ratios(shared);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_tiles: %s\n", e.what());
    return 1;
  }
  return 0;
}
