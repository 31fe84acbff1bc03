// yarnfit db …: validate, list, show and import fabric records.
#include <algorithm>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "fabrics_db/fab/fab_import.hpp"
#include "fabrics_db/import/tensile_import.hpp"
#include "fabrics_db/records/database.hpp"
#include "fabrics_db/records/fabric_summary.hpp"
#include "fabrics_db/text_util.hpp"
#include "reports/summaries/fabric_text.hpp"

namespace yarnfit::cli {
namespace {

namespace fs = std::filesystem;
using yarnfit::db::DatabaseLoad;
using yarnfit::db::Problems;

void print_problems(const Problems& problems) {
  for (const auto& p : problems.items()) std::cerr << p.to_string() << "\n";
}

// An import's problems on stderr, and "nothing written" when it wrote nothing; returns `written`.
bool say_problems(const Problems& problems, bool written) {
  print_problems(problems);
  if (!written) std::cerr << "nothing written\n";
  return written;
}

void print_notes(const DatabaseLoad& db) {
  for (const auto& n : db.notes) std::cerr << "note: " << n << "\n";
}

int run_validate(const fs::path& path) {
  const DatabaseLoad db = db::load_fabric_or_database(path);
  const Problems all = db.all_problems();
  print_notes(db);
  print_problems(all);
  for (const auto& f : db.fabrics) {
    const std::string name = f.id.empty() ? "(no id)" : f.id;
    if (f.ok()) {
      std::cout << "ok       " << name << "  " << f.folder.string() << "\n";
    } else {
      std::cout << "invalid  " << name << "  " << f.folder.string() << "  (" << f.problems.size()
                << " problem" << (f.problems.size() == 1 ? "" : "s") << ")\n";
    }
  }
  std::cout << db.fabrics.size() << " fabric" << (db.fabrics.size() == 1 ? "" : "s") << ": "
            << db.valid_count() << " valid, " << db.fabrics.size() - db.valid_count()
            << " invalid; " << all.size() << " problem" << (all.size() == 1 ? "" : "s") << "\n";
  return all.empty() ? k_exit_ok : k_exit_invalid_input;
}

int run_list(const fs::path& path, const std::string& family, bool as_json) {
  const DatabaseLoad db = db::load_fabric_or_database(path);
  nlohmann::json entries = nlohmann::json::array();
  Problems shown = db.problems;
  for (const auto& f : db.fabrics) {
    if (!family.empty() && f.family != family) continue;
    entries.push_back(db::list_entry(f));
    shown.append(f.problems);
  }
  print_notes(db);
  print_problems(shown);
  if (as_json) std::cout << entries.dump(2) << "\n";
  else reports::print_fabric_table(std::cout, entries);
  return shown.empty() ? k_exit_ok : k_exit_invalid_input;
}

int run_show(const fs::path& path, bool as_json) {
  if (!db::is_fabric_folder(path)) {
    std::cerr << (path / db::k_fabric_file_name).string()
              << ": file: no fabric here (db show takes one fabric folder)\n";
    return k_exit_invalid_input;
  }
  const auto load = db::load_fabric(path);
  if (!load.ok()) {
    print_problems(load.problems);
    return k_exit_invalid_input;
  }
  const auto j = db::describe_fabric(*load.fabric);
  if (as_json) std::cout << j.dump(2) << "\n";
  else reports::print_fabric(std::cout, j);
  return k_exit_ok;
}

struct ImportArgs {
  std::string input, output, stretch_col, force_col, width_col, compression_col;
  std::string extension_unit = "stretch", force_unit = "N", delimiter;
  double gauge_length_mm = 0.0, swatch_width_mm = 0.0;
  int skip_lines = -1;
  bool loading_branch = false, force = false, quiet = false;
};

int run_import(const ImportArgs& a) {
  db::TensileImportOptions o;
  o.input = a.input;
  o.output = a.output;
  o.extension = db::ColumnRef::parse(a.stretch_col);
  o.force = db::ColumnRef::parse(a.force_col);
  if (!a.width_col.empty()) o.width = db::ColumnRef::parse(a.width_col);
  if (!a.compression_col.empty()) o.compression = db::ColumnRef::parse(a.compression_col);
  o.extension_unit = *db::parse_extension_unit(a.extension_unit);  // checked by CLI11
  o.force_unit = *db::parse_force_unit(a.force_unit);
  if (a.gauge_length_mm > 0) o.gauge_length_mm = a.gauge_length_mm;
  if (a.swatch_width_mm > 0) o.swatch_width_mm = a.swatch_width_mm;
  if (a.skip_lines >= 0) o.skip_lines = a.skip_lines;
  if (a.delimiter == "tab" || a.delimiter == "\\t") o.delimiter = '\t';
  else if (!a.delimiter.empty()) o.delimiter = a.delimiter.front();
  o.loading_branch = a.loading_branch;
  o.overwrite = a.force;

  const auto r = db::import_tensile(o);
  if (!say_problems(r.problems, r.written)) return k_exit_invalid_input;
  if (!a.quiet) std::cout << reports::tensile_import_text(r, o.output.string());
  return k_exit_ok;
}

// The options bind straight to the importer's (`import`).
struct FabArgs {
  db::FabImportOptions import;
  bool quiet = false;
};

int run_import_fab(const FabArgs& a) {
  const auto r = db::import_fab(a.import);
  if (!say_problems(r.problems, r.written)) return k_exit_invalid_input;
  if (!a.quiet) std::cout << reports::fab_import_text(r, a.import.output.string());
  return k_exit_ok;
}

// Values the db subcommands parse into; shared by their callbacks, which outlive this call.
struct DbArgs {
  std::string path, family;
  bool json = false;
  ImportArgs import;
  FabArgs fab;
};

}  // namespace

void add_db_commands(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<DbArgs>();
  auto* db = app.add_subcommand("db", "Fabric records: validate, list, show, import");
  db->require_subcommand(1);

  auto* validate = db->add_subcommand(
      "validate",
      "Check a fabric folder or a database folder. Prints one 'file:line: field: message' "
      "per problem on stderr; exits 2 if there is any. Never modifies the files.");
  validate->add_option("PATH", args->path, "Fabric folder (with fabric.yaml) or database folder")
      ->required();
  validate->callback([args, &exit_code] { exit_code = run_validate(args->path); });

  auto* list = db->add_subcommand("list", "List the fabrics of a database");
  list->add_option("DB", args->path, "Database folder (or one fabric folder)")->required();
  list->add_option("--family", args->family, "Only fabrics of this family");
  list->add_flag("--json", args->json, "Print JSON instead of a table");
  list->callback([args, &exit_code] { exit_code = run_list(args->path, args->family, args->json); });

  auto* show = db->add_subcommand(
      "show", "Describe one fabric: composition, tests and curve ranges, tile facts");
  show->add_option("FABRIC", args->path, "Fabric folder")->required();
  show->add_flag("--json", args->json, "Print JSON (SI units) instead of text");
  show->callback([args, &exit_code] { exit_code = run_show(args->path, args->json); });

  auto* imp = db->add_subcommand(
      "import-tensile",
      "Turn a tensile-tester export into a stretch-test CSV (stretch, force_N[, compression]). "
      "Columns are given by header name or 1-based index. The header is found automatically "
      "when columns are named (lines above it are skipped). Writes a new file; an existing "
      "one is replaced only with --force.");
  ImportArgs& ia = args->import;
  imp->add_option("INPUT", ia.input, "Exported file (CSV, semicolon or tab separated)")->required();
  imp->add_option("-o,--out", ia.output, "Stretch-test CSV to write")->required();
  imp->add_option("--stretch-col", ia.stretch_col, "Column of the extension (mm) or stretch")->required();
  imp->add_option("--force-col", ia.force_col, "Column of the clamp force")->required();
  imp->add_option("--width-col", ia.width_col,
                  "Column of the fabric width at mid-length in mm (gives compression)");
  imp->add_option("--compression-col", ia.compression_col, "Column of compression c = 1 - w/w0");
  imp->add_option("--extension-unit", ia.extension_unit, "Unit of the extension column")
      ->check(CLI::IsMember({"mm", "stretch"}))
      ->capture_default_str();
  imp->add_option("--force-unit", ia.force_unit, "Unit of the force column")
      ->check(CLI::IsMember({"N", "cN", "mN", "kN"}))
      ->capture_default_str();
  imp->add_option("--gauge-length-mm", ia.gauge_length_mm,
                  "Initial length the extension is measured over (needed with mm)")
      ->check(CLI::PositiveNumber);
  imp->add_option("--swatch-width-mm", ia.swatch_width_mm,
                  "Unstretched swatch width (needed with --width-col)")
      ->check(CLI::PositiveNumber);
  imp->add_option("--skip-lines", ia.skip_lines, "Lines to skip before the header")
      ->check(CLI::NonNegativeNumber);
  imp->add_option("--delimiter", ia.delimiter, "Field separator: ',', ';' or 'tab' (detected if absent)");
  imp->add_flag("--loading-branch", ia.loading_branch,
                "Keep only the loading branch: rows up to the peak force whose stretch increases");
  imp->add_flag("--force", ia.force, "Replace the output file if it exists");
  imp->add_flag("-q,--quiet", ia.quiet, "Print nothing on success");
  imp->callback([args, &exit_code] { exit_code = run_import(args->import); });

  auto* fab = db->add_subcommand(
      "import-fab",
      "Make a fabric record from a Browzwear FAB measurement (U3M 1.1 physics .json, a .u3m naming "
      "one, or a .u3ma): every test with its cycles and branches in SI units under fab_tests, the "
      "physics file kept unchanged, each grain's 8 cm stretch as a stretch test (docs/fab.md). "
      "Exits 2 naming the file and the JSON path of every problem; nothing is written then.");
  FabArgs& fa = args->fab;
  fab->add_option("FILE", fa.import.input, "The FAB measurement (.json, .u3m or .u3ma)")->required();
  fab->add_option("-o,--out", fa.import.output, "The record's folder to create (must not exist)")->required();
  fab->add_option("--denier", fa.import.denier,
                  "The yarn's linear density, grams per 9,000 m (the FAB does not measure it)")
      ->required()
      ->check(CLI::PositiveNumber);
  fab->add_option("--id", fa.import.id, "The record's id (default: the folder's name)");
  fab->add_option("--family", fa.import.family, "The record's family (default: the file's category, else 'fab')");
  fab->add_option("--material", fa.import.material, "The yarn's material (default: the file's composition)");
  fab->add_option("--tile", fa.import.tile, "A periodic yarn tile (.pyp) for a yarn stage, copied into the record");
  fab->add_option("--knit", fa.import.knit, "A knit chart to generate the tile from, with the two options below");
  fab->add_option("--stitch-length-mm", fa.import.stitch_length_mm, "Stitch length, with --knit")->check(CLI::PositiveNumber);
  fab->add_option("--yarn-radius-mm", fa.import.yarn_radius_mm, "Yarn radius, with --knit")->check(CLI::PositiveNumber);
  fab->add_flag("-q,--quiet", fa.quiet, "Print nothing on success");
  fab->callback([args, &exit_code] { exit_code = run_import_fab(args->fab); });
}

}  // namespace yarnfit::cli
