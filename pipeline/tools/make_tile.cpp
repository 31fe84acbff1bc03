#include "pipeline/tools/make_tile.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "fabrics_db/records/fabric.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/woven_tile.hpp"
#include "numerics/util/error.hpp"
#include "results/tile_file.hpp"
#include "yarn_fit/generate/knit_generation.hpp"

namespace yarnfit::pipeline {
namespace {

using db::format_g;

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

void refuse_existing(const TileRequest& r, db::Problems& problems) {
  if (std::filesystem::exists(r.out) && !r.force) problems.add(r.out, 0, "file", "exists (pass --force to replace it)");
}

MadeTile make_woven_tile(const TileRequest& r, db::Problems& problems) {
  std::string why;
  const auto chart = db::parse_weave_chart(r.weave, &why);
  if (!chart) problems.add_field("weave", why);
  if (!r.chart.empty()) problems.add_field("chart", "give either a knit chart or --weave, not both");
  if (r.stitch_length_mm != 0.0) problems.add_field("stitch_length_mm", "a woven tile takes --yarn-spacing-mm");
  db::WovenTileOptions o;
  o.yarn_spacing = 1e-3 * r.yarn_spacing_mm;
  o.yarn_radius = 1e-3 * r.yarn_radius_mm;
  o.weft_crimp_share = r.weft_crimp_share.value_or(o.weft_crimp_share);
  const db::Problems geometry = o.problems();
  for (const auto& p : geometry.items())
    problems.add_field("woven geometry (yarn spacing, yarn radius, weft crimp share)", p.to_string());
  refuse_existing(r, problems);
  if (!problems.empty()) return {};

  const db::PeriodicTile tile = db::make_woven_tile(*chart, o);
  db::write_pyp(tile, r.out);
  MadeTile made;
  made.written = true;
  made.facts = results::to_json(results::WovenTileFile{
      chart->name, chart->text(), {1e3 * tile.period_x, 1e3 * tile.period_y}, r.yarn_spacing_mm, r.yarn_radius_mm,
      static_cast<long long>(tile.vertex_count()), r.out, o.weft_crimp_share});
  std::ostringstream s;
  s << "tile make --weave " << r.weave << " (" << chart->text() << "), yarns " << format_g(r.yarn_spacing_mm)
    << " mm apart, R " << format_g(r.yarn_radius_mm) << " mm, weft crimp share " << format_g(o.weft_crimp_share)
    << ": " << chart->warps() << " warps x " << chart->wefts() << " wefts, " << tile.vertex_count()
    << " vertices, period " << format_g(1e3 * tile.period_x, 4) << " x " << format_g(1e3 * tile.period_y, 4)
    << " mm\n"
    << "  as constructed (not relaxed: the yarn commands relax it at rest); wrote " << r.out << "\n";
  made.summary = s.str();
  return made;
}

// The knit's generation options from the request; its problems into `problems`.
yarn::TileGenerationOptions knit_options(const TileRequest& r, db::Problems& problems) {
  yarn::TileGenerationOptions o;
  o.geometry.stitch_length = 1e-3 * r.stitch_length_mm;
  o.geometry.yarn_radius = 1e-3 * r.yarn_radius_mm;
  o.geometry.vertices_per_stitch = r.vertices_per_stitch;
  o.default_ks2 = r.ks2;
  if (!r.gauge.empty()) {
    if (r.gauge.size() != 2 || !(positive(r.gauge[0]) && positive(r.gauge[1])))
      problems.add_field("gauge", "courses and wales per 10 cm, two positive numbers (e.g. --gauge 52,38)");
    else {
      const db::KnittingGauge gauge{r.gauge[0], r.gauge[1]};
      o.geometry.wale_spacing = gauge.wale_spacing();
      o.geometry.course_spacing = gauge.course_spacing();
    }
    if (r.aspect != 0.0) problems.add_field("aspect", "the gauge sets the aspect; give one or the other");
  }
  if (r.aspect != 0.0) {
    if (!positive(r.aspect)) problems.add_field("aspect", "must be a positive ratio");
    else o.geometry.course_ratio = r.aspect;
  }
  return o;
}

std::string knit_summary(const TileRequest& r, const db::KnitChart& chart, const yarn::GeneratedTile& t) {
  const auto mm = [](double metres) { return format_g(1e3 * metres, 4); };
  std::ostringstream s;
  s << "tile make " << r.chart << " (" << chart.text() << "), L " << format_g(r.stitch_length_mm) << " mm, R "
    << format_g(r.yarn_radius_mm) << " mm: " << chart.wales() << " x " << chart.courses() << " stitches, "
    << t.tile.vertex_count() << " vertices\n"
    << "  period " << mm(t.tile.period_x) << " x " << mm(t.tile.period_y) << " mm: wales " << mm(t.wale_spacing())
    << " mm apart (" << format_g(1e-2 / t.wale_spacing(), 4) << " per cm), courses " << mm(t.course_spacing())
    << " mm apart (" << format_g(1e-2 / t.course_spacing(), 4) << " per cm)\n"
    << "  rest stress " << format_g(100.0 * t.rest_stress_ratio, 3) << " % of sigma_s at 10 % stretch (weft "
    << format_g(t.stress_at_10[0], 4) << ", warp " << format_g(t.stress_at_10[1], 4) << " N/m); closest yarns "
    << mm(t.min_distance) << " mm apart\n"
    << "  " << (t.converged ? "relaxed" : "NOT relaxed: " + t.message) << " in " << format_g(t.seconds, 3) << " s"
    << (t.converged ? "; wrote " + r.out : std::string()) << "\n";
  return s.str();
}

MadeTile make_knit_tile(const TileRequest& r, db::Problems& problems) {
  std::string why;
  const auto chart = db::parse_knit_chart(r.chart, &why);
  if (!chart) problems.add_field("chart", r.chart.empty() ? std::string("a knit chart (or --weave) is required") : why);
  if (r.yarn_spacing_mm != 0.0) problems.add_field("yarn_spacing_mm", "only for a woven tile (--weave)");
  if (r.weft_crimp_share) problems.add_field("weft_crimp_share", "only for a woven tile (--weave)");
  if (!positive(r.stitch_length_mm)) problems.add_field("stitch_length_mm", "must be a positive length in millimetres");
  if (!positive(r.yarn_radius_mm)) problems.add_field("yarn_radius_mm", "must be a positive length in millimetres");
  if (!positive(r.ks2)) problems.add_field("ks2", "must be a positive stiffness [N]");
  refuse_existing(r, problems);
  yarn::TileGenerationOptions o = knit_options(r, problems);
  if (!r.params_file.empty() && problems.empty()) {
    const auto params = yarn::read_yarn_params(r.params_file, yarn::ParameterScales{r.ks2, o.geometry.yarn_radius}, problems);
    if (params) o.params = *params;
  }
  if (problems.empty()) problems.append(o.geometry.problems());
  if (!problems.empty()) return {};

  yarn::GeneratedTile t;
  try {
    t = yarn::generate_knit_tile(*chart, o);
  } catch (const Error& e) {  // loops that cannot be built at this length or gauge
    if (e.category() != ErrorCategory::input) throw;  // only a refused chart or geometry is the user's
    problems.add_field("tile", e.what());
    return {};
  }
  MadeTile made;
  if (t.converged) {
    db::write_pyp(t.tile, r.out);
    made.written = true;
  } else {
    made.failure = t.message;
  }
  results::TileFile record = yarn::to_file(t);
  record.file = t.converged ? r.out : "";
  made.facts = results::to_json(record);
  made.summary = knit_summary(r, *chart, t);
  return made;
}

}  // namespace

MadeTile make_tile(const TileRequest& request, db::Problems& problems) {
  return request.weave.empty() ? make_knit_tile(request, problems) : make_woven_tile(request, problems);
}

}  // namespace yarnfit::pipeline
