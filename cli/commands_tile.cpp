// `yarnfit tile make`: a relaxed periodic yarn tile of a knit from its chart, stitch length and
// yarn radius (issue 20), or a woven tile from its weave chart, yarn spacing and radius (issue
// 37); pipeline/tools/make_tile.hpp makes it.
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "pipeline/tools/make_tile.hpp"

namespace yarnfit::cli {
namespace {

struct TileMakeArgs {
  pipeline::TileRequest request;
  bool json = false;
  bool quiet = false;
};

int run_tile_make(const TileMakeArgs& a) {
  db::Problems problems;
  pipeline::MadeTile made;
  if (!write_files(a.request.out, [&] { made = pipeline::make_tile(a.request, problems); })) return k_exit_internal;
  if (!problems.empty()) return invalid_input(problems, "tile make: ");
  if (a.json) std::cout << made.facts.dump(2) << "\n";
  else if (!a.quiet) std::cout << made.summary;
  if (!made.written) {
    std::cerr << "tile make: " << made.failure << "; nothing written\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

}  // namespace

void add_tile_commands(CLI::App& app, int& exit_code) {
  auto* tile = app.add_subcommand("tile", "Periodic yarn tiles generated for real knits");
  tile->require_subcommand(1);
  auto args = std::make_shared<TileMakeArgs>();
  pipeline::TileRequest& r = args->request;
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
  make->add_option("--chart", r.chart,
                   "Named chart (" + names +
                       ") or rows of k (knit) and p (purl) as the fabric's face shows them, lowest course first, "
                       "separated by '/', e.g. kp/pk");
  std::string weaves;
  for (const auto& n : db::named_weave_charts()) weaves += (weaves.empty() ? "" : ", ") + n;
  make->add_option("--weave", r.weave,
                   "A woven tile instead of a knit: named weave (" + weaves +
                       ") or rows of 1 (warp on top) and 0 (weft on top), one row per weft yarn, lowest first, "
                       "separated by '/', e.g. 10/01");
  make->add_option("--stitch-length-mm", r.stitch_length_mm, "Yarn length per stitch [mm] (knits)");
  make->add_option("--yarn-spacing-mm", r.yarn_spacing_mm,
                   "Centre distance of neighbouring parallel yarns [mm] (woven tiles)");
  make->add_option("--yarn-radius-mm", r.yarn_radius_mm, "Yarn radius [mm]")->required();
  make->add_option("--weft-crimp-share", r.weft_crimp_share,
                   "The weft's share of the crimp at a crossing, in (0, 1): the weft swings over that fraction of "
                   "the two yarns' height difference, the warp over the rest (woven tiles; default " +
                       db::format_g(db::WovenTileOptions{}.weft_crimp_share) + ": the warp, woven under tension, keeps less)");
  make->add_option("--gauge", r.gauge,
                   "Knitting gauge, courses and wales per 10 cm (e.g. 52,38): the loops are built at this period and "
                   "hold it; the rest lengths and curvatures absorb the rest stress (knits)")
      ->delimiter(',')
      ->expected(2);
  make->add_option("--aspect", r.aspect,
                   "Course spacing over wale spacing of the loops without a gauge (default: Crane's 0.716) (knits)");
  make->add_option("-o,--out", r.out, "The tile to write (.pyp)")->required();
  make->add_option("--params", r.params_file,
                   "Yarn parameters (YAML/JSON, keys of yarn_fit.json's params); default: SPEC section 3's "
                   "defaults with R_est = the yarn radius");
  make->add_option("--ks2", r.ks2, "Yarn stretch stiffness for the default parameters [N]")
      ->capture_default_str();
  make->add_option("--vertices-per-stitch", r.vertices_per_stitch, "Polyline vertices per stitch")
      ->check(CLI::Range(8, 200))
      ->capture_default_str();
  make->add_flag("--json", args->json, "Print the relaxed tile's facts as JSON");
  make->add_flag("--force", r.force, "Replace an existing file");
  make->add_flag("-q,--quiet", args->quiet, "No summary");
  make->callback([args, &exit_code] { exit_code = run_tile_make(*args); });
}

}  // namespace yarnfit::cli
