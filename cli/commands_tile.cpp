// `yarnfit tile make`: a relaxed periodic yarn tile of a knit from its chart, stitch length and
// yarn radius (issue 20; yarn_fit/generate/knit_generation.hpp), or a woven tile from its
// weave chart, yarn spacing and radius (issue 37; fabrics_db/tile/woven_tile.hpp).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "cli/commands.hpp"
#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "yarn_fit/generate/knit_generation.hpp"

namespace yarnfit::cli {
namespace {

struct TileMakeArgs {
  std::string chart, weave, out, params_file;
  double stitch_length_mm = 0.0;
  double yarn_spacing_mm = 0.0;
  std::optional<double> weft_crimp_share;  // woven tiles; unset: WovenTileOptions' default
  double yarn_radius_mm = 0.0;
  double ks2 = 400.0;
  std::vector<double> gauge;  // courses, wales per 10 cm
  double aspect = 0.0;        // course / wale spacing (0: Crane's)
  int vertices_per_stitch = 16;
  bool json = false;
  bool force = false;
  bool quiet = false;
};

// A woven tile as constructed (the yarn commands relax it at rest before they simulate).
int run_weave_make(const TileMakeArgs& a) {
  std::vector<std::string> problems;
  std::string why;
  const auto chart = db::parse_weave_chart(a.weave, &why);
  if (!chart) problems.push_back("--weave: " + why);
  if (!a.chart.empty()) problems.push_back("--chart: give either a knit chart or --weave, not both");
  if (a.stitch_length_mm != 0.0) problems.push_back("--stitch-length-mm: a woven tile takes --yarn-spacing-mm");
  db::WovenTileOptions o;
  o.yarn_spacing = 1e-3 * a.yarn_spacing_mm;
  o.yarn_radius = 1e-3 * a.yarn_radius_mm;
  o.weft_crimp_share = a.weft_crimp_share.value_or(o.weft_crimp_share);
  const db::Problems weave = o.problems();
  for (const auto& p : weave.items()) problems.push_back("woven geometry (--yarn-spacing-mm, --yarn-radius-mm, --weft-crimp-share): " + p.to_string());
  if (std::filesystem::exists(a.out) && !a.force) problems.push_back(a.out + ": exists (pass --force to replace it)");
  if (!problems.empty()) {
    for (const auto& p : problems) std::cerr << "tile make: " << p << "\n";
    return k_exit_invalid_input;
  }
  const db::PeriodicTile tile = db::make_woven_tile(*chart, o);
  if (!write_files(a.out, [&] { db::write_pyp(tile, a.out); })) return k_exit_internal;
  if (a.json) {
    const results::WovenTileFile record{chart->name,      chart->text(),     {1e3 * tile.period_x, 1e3 * tile.period_y},
                                        a.yarn_spacing_mm, a.yarn_radius_mm, static_cast<long long>(tile.vertex_count()),
                                        a.out,             o.weft_crimp_share};
    std::cout << results::to_json(record).dump(2)
              << "\n";
  } else if (!a.quiet) {
    std::cout << "tile make --weave " << a.weave << " (" << chart->text() << "), yarns "
              << db::format_g(a.yarn_spacing_mm) << " mm apart, R " << db::format_g(a.yarn_radius_mm)
              << " mm, weft crimp share " << db::format_g(o.weft_crimp_share) << ": " << chart->warps()
              << " warps x " << chart->wefts() << " wefts, " << tile.vertex_count()
              << " vertices, period " << db::format_g(1e3 * tile.period_x, 4) << " x "
              << db::format_g(1e3 * tile.period_y, 4) << " mm\n"
              << "  as constructed (not relaxed: the yarn commands relax it at rest); wrote " << a.out << "\n";
  }
  return k_exit_ok;
}

int run_tile_make(const TileMakeArgs& a) {
  if (!a.weave.empty()) return run_weave_make(a);
  std::vector<std::string> problems;
  std::string why;
  const auto chart = db::parse_knit_chart(a.chart, &why);
  if (!chart) problems.push_back("--chart: " + (a.chart.empty() ? std::string("a knit chart (or --weave) is required") : why));
  if (a.yarn_spacing_mm != 0.0) problems.push_back("--yarn-spacing-mm: only for a woven tile (--weave)");
  if (a.weft_crimp_share) problems.push_back("--weft-crimp-share: only for a woven tile (--weave)");
  if (!(std::isfinite(a.stitch_length_mm) && a.stitch_length_mm > 0.0))
    problems.push_back("--stitch-length-mm: must be a positive length in millimetres");
  if (!(std::isfinite(a.yarn_radius_mm) && a.yarn_radius_mm > 0.0))
    problems.push_back("--yarn-radius-mm: must be a positive length in millimetres");
  if (!(std::isfinite(a.ks2) && a.ks2 > 0.0)) problems.push_back("--ks2: must be a positive stiffness [N]");
  if (std::filesystem::exists(a.out) && !a.force)
    problems.push_back(a.out + ": exists (pass --force to replace it)");
  yarn::TileGenerationOptions o;
  o.geometry.stitch_length = 1e-3 * a.stitch_length_mm;
  o.geometry.yarn_radius = 1e-3 * a.yarn_radius_mm;
  o.geometry.vertices_per_stitch = a.vertices_per_stitch;
  o.default_ks2 = a.ks2;
  if (!a.gauge.empty()) {
    if (a.gauge.size() != 2 || !(a.gauge[0] > 0.0 && a.gauge[1] > 0.0 && std::isfinite(a.gauge[0] + a.gauge[1])))
      problems.push_back("--gauge: courses and wales per 10 cm, two positive numbers (e.g. --gauge 52,38)");
    else {
      const db::KnittingGauge gauge{a.gauge[0], a.gauge[1]};
      o.geometry.wale_spacing = gauge.wale_spacing();
      o.geometry.course_spacing = gauge.course_spacing();
    }
    if (a.aspect != 0.0) problems.push_back("--aspect: the gauge sets the aspect; give one or the other");
  }
  if (a.aspect != 0.0) {
    if (!(std::isfinite(a.aspect) && a.aspect > 0.0)) problems.push_back("--aspect: must be a positive ratio");
    else o.geometry.course_ratio = a.aspect;
  }
  if (!a.params_file.empty() && problems.empty()) {
    db::Problems found;
    const auto params = yarn::read_yarn_params(a.params_file, yarn::ParameterScales{a.ks2, o.geometry.yarn_radius}, found);
    for (const auto& p : found.items()) problems.push_back(p.to_string());
    if (params) o.params = *params;
  }
  if (problems.empty()) {
    const db::Problems geometry = o.geometry.problems();
    for (const auto& p : geometry.items()) problems.push_back(p.to_string());
  }
  if (!problems.empty()) {
    for (const auto& p : problems) std::cerr << "tile make: " << p << "\n";
    return k_exit_invalid_input;
  }
  yarn::GeneratedTile t;
  try {
    t = yarn::generate_knit_tile(*chart, o);
  } catch (const std::invalid_argument& e) {
    std::cerr << "tile make: " << e.what() << "\n";
    return k_exit_invalid_input;
  }
  if (t.converged && !write_files(a.out, [&] { db::write_pyp(t.tile, a.out); })) return k_exit_internal;
  if (a.json) {
    results::TileFile record = yarn::to_file(t);
    record.file = t.converged ? a.out : "";
    std::cout << results::to_json(record).dump(2) << "\n";
  } else if (!a.quiet) {
    const auto mm = [](double metres) { return db::format_g(1e3 * metres, 4); };
    std::cout << "tile make " << a.chart << " (" << chart->text() << "), L " << db::format_g(a.stitch_length_mm)
              << " mm, R " << db::format_g(a.yarn_radius_mm) << " mm: " << chart->wales() << " x " << chart->courses()
              << " stitches, " << t.tile.vertex_count() << " vertices\n"
              << "  period " << mm(t.tile.period_x) << " x " << mm(t.tile.period_y) << " mm: wales "
              << mm(t.wale_spacing()) << " mm apart (" << db::format_g(1e-2 / t.wale_spacing(), 4)
              << " per cm), courses " << mm(t.course_spacing()) << " mm apart ("
              << db::format_g(1e-2 / t.course_spacing(), 4) << " per cm)\n"
              << "  rest stress " << db::format_g(100.0 * t.rest_stress_ratio, 3)
              << " % of sigma_s at 10 % stretch (weft " << db::format_g(t.stress_at_10[0], 4) << ", warp "
              << db::format_g(t.stress_at_10[1], 4) << " N/m); closest yarns " << mm(t.min_distance) << " mm apart\n"
              << "  " << (t.converged ? "relaxed" : "NOT relaxed: " + t.message) << " in "
              << db::format_g(t.seconds, 3) << " s" << (t.converged ? "; wrote " + a.out : std::string()) << "\n";
  }
  if (!t.converged) {
    std::cerr << "tile make: " << t.message << "; nothing written\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

}  // namespace

void add_tile_commands(CLI::App& app, int& exit_code) {
  auto* tile = app.add_subcommand("tile", "Periodic yarn tiles generated for real knits");
  tile->require_subcommand(1);
  auto args = std::make_shared<TileMakeArgs>();
  auto* make = tile->add_subcommand(
      "make",
      "Generate a periodic yarn tile of a knit from its chart, stitch length and yarn radius, relax it (yarns at "
      "rest, contacts resolved, period relaxed until the coarse stress at rest is at most 1 % of sigma_s at 10 % "
      "stretch in weft and warp) and write it as a pyp file (x axis along the weft). JSON: chart, period_mm, "
      "wale_spacing_mm, course_spacing_mm, courses_per_cm, wales_per_cm, stitch_length_mm, yarn_radius_mm, "
      "rest_stress_ratio, converged, seconds, params. Exit 1, writing nothing, when the relaxation fails. "
      "With --weave instead of --chart: a woven tile from its weave chart, yarn spacing and radius, as constructed "
      "(wefts along x, warps along y; not relaxed).");
  std::string names;
  for (const auto& n : db::named_knit_charts()) names += (names.empty() ? "" : ", ") + n;
  make->add_option("--chart", args->chart,
                   "Named chart (" + names +
                       ") or rows of k (knit) and p (purl) as the fabric's face shows them, lowest course first, "
                       "separated by '/', e.g. kp/pk");
  std::string weaves;
  for (const auto& n : db::named_weave_charts()) weaves += (weaves.empty() ? "" : ", ") + n;
  make->add_option("--weave", args->weave,
                   "A woven tile instead of a knit: named weave (" + weaves +
                       ") or rows of 1 (warp on top) and 0 (weft on top), one row per weft yarn, lowest first, "
                       "separated by '/', e.g. 10/01");
  make->add_option("--stitch-length-mm", args->stitch_length_mm, "Yarn length per stitch [mm] (knits)");
  make->add_option("--yarn-spacing-mm", args->yarn_spacing_mm,
                   "Centre distance of neighbouring parallel yarns [mm] (woven tiles)");
  make->add_option("--yarn-radius-mm", args->yarn_radius_mm, "Yarn radius [mm]")->required();
  make->add_option("--weft-crimp-share", args->weft_crimp_share,
                   "The weft's share of the crimp at a crossing, in (0, 1): the weft swings over that fraction of "
                   "the two yarns' height difference, the warp over the rest (woven tiles; default " +
                       db::format_g(db::WovenTileOptions{}.weft_crimp_share) + ": the warp, woven under tension, keeps less)");
  make->add_option("--gauge", args->gauge,
                   "Knitting gauge, courses and wales per 10 cm (e.g. 52,38): the loops are built at this period and "
                   "hold it; the rest lengths and curvatures absorb the rest stress (knits)")
      ->delimiter(',')
      ->expected(2);
  make->add_option("--aspect", args->aspect,
                   "Course spacing over wale spacing of the loops without a gauge (default: Crane's 0.716) (knits)");
  make->add_option("-o,--out", args->out, "The tile to write (.pyp)")->required();
  make->add_option("--params", args->params_file,
                   "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params); default: SPEC section 3's "
                   "defaults with R_est = the yarn radius");
  make->add_option("--ks2", args->ks2, "Yarn stretch stiffness for the default parameters [N]")
      ->capture_default_str();
  make->add_option("--vertices-per-stitch", args->vertices_per_stitch, "Polyline vertices per stitch")
      ->check(CLI::Range(8, 200))
      ->capture_default_str();
  make->add_flag("--json", args->json, "Print the relaxed tile's facts as JSON");
  make->add_flag("--force", args->force, "Replace an existing file");
  make->add_flag("-q,--quiet", args->quiet, "No summary");
  make->callback([args, &exit_code] { exit_code = run_tile_make(*args); });
}

}  // namespace yarnfit::cli
