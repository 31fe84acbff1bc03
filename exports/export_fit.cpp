#include "exports/export_fit.hpp"

#include <cmath>
#include <cstdio>

#include "exports/arcsim_material.hpp"
#include "exports/fitted_fabric.hpp"
#include "exports/strain_table.hpp"
#include "exports/u3m_material.hpp"
#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::exports {

namespace {

std::string percent(double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f %%", v);
  return buf;
}

ExportOutcome export_arcsim(const FittedFabric& fabric, const std::filesystem::path& out) {
  const ArcsimMaterial material = arcsim_material(fabric);
  const std::vector<ArcsimDeviation> deviation = arcsim_deviation(fabric, material);
  db::write_text_file_atomically(out, arcsim_json(fabric, material, deviation).dump(2) + "\n");
  ExportOutcome o;
  o.files.push_back(out);
  o.text = "ARCSim material of " + fabric.shell.fabric + " written to " + out.string() + "\n" +
           "uniaxial force, ARCSim's model against the fitted law over the comfort range (goal <= " +
           percent(k_arcsim_goal_pct) + " mean):\n";
  for (const auto& d : deviation) {
    char line[160];
    std::snprintf(line, sizeof line, "  %-5s to stretch %.3f: mean %s, largest %s%s\n", d.direction.c_str(),
                  d.comfort_stretch, percent(d.mean_pct).c_str(), percent(d.max_pct).c_str(),
                  std::isfinite(d.mean_pct) && d.mean_pct <= k_arcsim_goal_pct ? "" : "  (goal missed)");
    o.text += line;
  }
  return o;
}

ExportOutcome export_u3m(const FittedFabric& fabric, const std::filesystem::path& out) {
  const U3mMaterial u3m = u3m_material(fabric);
  ExportOutcome o;
  if (out.extension() == ".u3ma") {
    write_u3ma(u3m, out);
    o.files.push_back(out);
  } else {
    o.files = write_u3m_folder(u3m, out);
  }
  o.text = "U3M 1.1 material of " + fabric.shell.fabric + " written to " + out.string() +
           (out.extension() == ".u3ma" ? " (zipped)" : ": " + u3m.name + ".u3m, physics/physics.json") + "\n";
  if (!fabric.record_fabric)
    o.text += "  without the record (--record): weight, composition and construction are null\n";
  return o;
}

ExportOutcome export_table(const FittedFabric& fabric, const std::filesystem::path& out,
                           const std::filesystem::path& tile_cache) {
  const StrainTable table = strain_table(fabric, tile_cache);
  std::filesystem::create_directories(out);
  ExportOutcome o;
  const auto write = [&](const std::string& name, const std::string& text) {
    db::write_text_file_atomically(out / name, text);
    o.files.push_back(out / name);
  };
  write("stress.csv", stress_csv(table));
  write("uniaxial.csv", uniaxial_csv(table));
  write("bending.csv", bending_csv(table));
  write("table.json", table_json(fabric, table).dump(1) + "\n");
  o.text = "strain table of " + fabric.shell.fabric + " written to " + out.string() + ": stress.csv (" +
           std::to_string(table.stress.size()) + " strains), uniaxial.csv (" + std::to_string(table.uniaxial.size()) +
           " rows" + (table.yarn_reason.empty() ? ", shell and yarn" : ", shell only: " + table.yarn_reason) +
           "), bending.csv (" + (table.yarn_bending_reason.empty() ? "shell and yarn" : "shell only: " + table.yarn_bending_reason) +
           "), table.json\n";
  return o;
}

// Where the fit kept a knit's generated tile: as given, else BATCH/tiles for a batch fabric
// folder (BATCH/fabrics/<id>), else the fit folder itself (`fit`'s).
std::filesystem::path tile_cache_of(const ExportRequest& request) {
  if (!request.tile_cache.empty()) return request.tile_cache;
  std::filesystem::path dir = std::filesystem::absolute(request.fit_dir).lexically_normal();
  if (!dir.has_filename()) dir = dir.parent_path();  // given with a trailing '/'
  const std::filesystem::path batch = dir.parent_path().parent_path();
  return std::filesystem::exists(batch / "batch.db") ? batch / "tiles" : request.fit_dir;
}

}  // namespace

std::optional<ExportFormat> export_format_from_string(std::string_view name) {
  if (name == "u3m") return ExportFormat::u3m;
  if (name == "arcsim") return ExportFormat::arcsim;
  if (name == "table") return ExportFormat::table;
  return std::nullopt;
}

const char* to_string(ExportFormat format) {
  switch (format) {
    case ExportFormat::u3m: return "u3m";
    case ExportFormat::arcsim: return "arcsim";
    case ExportFormat::table: break;
  }
  return "table";
}

std::filesystem::path export_path(ExportFormat format, const std::string& fabric_id) {
  switch (format) {
    case ExportFormat::u3m: return std::filesystem::path("exports") / (fabric_id + ".u3ma");
    case ExportFormat::arcsim: return std::filesystem::path("exports") / (fabric_id + "_arcsim.json");
    case ExportFormat::table: break;
  }
  return std::filesystem::path("exports") / "table";
}

ExportOutcome export_fit(const ExportRequest& request) {
  if (!request.overwrite && std::filesystem::exists(request.out))
    throw Error(ErrorCategory::conflict, request.out.string() + ": exists (use --force to replace it)");
  FittedFabric fabric = read_fitted_fabric(request.fit_dir, request.record);
  if (request.areal_density_gsm) {
    if (!(*request.areal_density_gsm > 0.0)) throw Error(ErrorCategory::input, "areal_density_gsm: must be positive");
    fabric.areal_density = *request.areal_density_gsm * 1e-3;
  }
  if (request.out.has_parent_path()) std::filesystem::create_directories(request.out.parent_path());
  switch (request.format) {
    case ExportFormat::u3m: return export_u3m(fabric, request.out);
    case ExportFormat::arcsim: return export_arcsim(fabric, request.out);
    case ExportFormat::table: break;
  }
  return export_table(fabric, request.out, tile_cache_of(request));
}

}  // namespace yarnfit::exports
