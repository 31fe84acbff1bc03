// yarnfit export FIT_DIR --format arcsim --out PATH: a fitted fabric in another simulator's
// format (SPEC §5; exports/export_fit.hpp does the work).
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "exports/export_fit.hpp"
#include "exports/fitted_fabric.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::cli {

namespace {

struct ExportArgs {
  std::string fit_dir, format, out, record, tile_cache;
  std::optional<double> areal_density_gsm;
  bool force = false;
};

int run_export(const ExportArgs& a) {
  exports::ExportRequest r;
  r.fit_dir = a.fit_dir;
  r.format = *exports::export_format_from_string(a.format);
  r.out = a.out;
  r.record = a.record;
  r.overwrite = a.force;
  r.areal_density_gsm = a.areal_density_gsm;
  r.tile_cache = a.tile_cache;
  try {
    std::cout << exports::export_fit(r).text;
  } catch (const Error& e) {
    std::cerr << "export: " << (e.users_to_mend() ? "" : a.out + ": ") << e.what() << "\n";
    return exit_code_of(e);
  } catch (const std::exception& e) {
    std::cerr << "export: " << a.out << ": " << e.what() << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

}  // namespace

void add_export_command(CLI::App& app, int& exit_code) {
  auto a = std::make_shared<ExportArgs>();
  auto* e = app.add_subcommand(
      "export", "A fitted fabric in another simulator's format (docs/exports.md): u3m, a U3M 1.1 material (Browzwear, "
                "CLO) whose physics file carries the fitted model, as a folder or a zipped .u3ma; arcsim, ARCSim's "
                "material data file "
                "(Wang et al. 2011's model) sampled from the fitted shell law, with how far its uniaxial force strays "
                "from the law over the comfort range; table, the homogenised response as CSV and JSON tables (the "
                "shell law's stress on a Green-strain grid, uniaxial pulls of the shell law and the fitted yarn "
                "model, bending)");
  e->add_option("FIT_DIR", a->fit_dir, "A `yarnfit fit` output folder or a batch fabric folder")->required();
  e->add_option("--format", a->format, "u3m, arcsim or table")->required()->check(CLI::IsMember({"u3m", "arcsim", "table"}));
  e->add_option("-o,--out", a->out, "What to write: u3m, a folder or a .u3ma file; arcsim, a .json file; table, a folder")
      ->required();
  e->add_option("--record", a->record,
                "The fabric's record folder: its areal density (ARCSim needs it; U3M's weight), yarns (U3M's "
                "composition), knit (U3M's construction), tile (the table's yarn bending) and fingerprint");
  e->add_option("--areal-density-gsm", a->areal_density_gsm, "The fabric's areal density [g/m^2], when its record has none");
  e->add_option("--tile-cache", a->tile_cache,
                "table: where the fit kept a knit's generated tile (default: FIT_DIR, or BATCH/tiles for a batch fabric folder)");
  e->add_flag("--force", a->force, "Replace the output when it exists");
  e->callback([a, &exit_code] { exit_code = run_export(*a); });
}

}  // namespace yarnfit::cli
