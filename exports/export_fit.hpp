#pragma once
// `yarnfit export FIT_DIR --format F --out PATH` as a library call: the fit read
// (fitted_fabric.hpp), the format made, its file written whole (or not at all), and the lines a
// terminal shows, among them how far the format strays from the fitted law.
//
//   exports::ExportRequest r{"out/demo", exports::ExportFormat::arcsim, "demo_arcsim.json"};
//   r.record = "examples/fabrics/stockinette_demo";
//   std::cout << exports::export_fit(r).text;   // throws an Error on bad input

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace yarnfit::exports {

enum class ExportFormat { u3m, arcsim, table };
[[nodiscard]] std::optional<ExportFormat> export_format_from_string(std::string_view name);
[[nodiscard]] const char* to_string(ExportFormat format);

// Where a fit writes its exports (`fit --export`, a batch's, a service job's), relative to its
// output folder: exports/<id>.u3ma, exports/<id>_arcsim.json, exports/table/.
[[nodiscard]] std::filesystem::path export_path(ExportFormat format, const std::string& fabric_id);

struct ExportRequest {
  std::filesystem::path fit_dir;
  ExportFormat format = ExportFormat::arcsim;
  std::filesystem::path out;     // u3m: a folder, or a .u3ma file; arcsim: the material file; table: a folder
  std::filesystem::path record;  // the fabric's record folder (areal density); may be empty
  std::optional<double> areal_density_gsm;  // given: wins over the record's [g/m²]
  // Where a knit's generated tile was kept (table: the yarn bending rows); empty: the fit folder.
  std::filesystem::path tile_cache;
  bool overwrite = false;        // replace `out` when it exists; otherwise that refuses the export
};

struct ExportOutcome {
  std::vector<std::filesystem::path> files;
  std::string text;  // what was written and the deviations, for a terminal
};

// Throws an Error (exit 2 in the command) for a folder without a usable fit, a record that
// does not match, a format that lacks what it needs, or an output that exists.
ExportOutcome export_fit(const ExportRequest& request);

}  // namespace yarnfit::exports
