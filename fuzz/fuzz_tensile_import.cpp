// A tensile tester's export turned into a stretch-test CSV (`yarnfit db import`), columns
// found by number, header lines and delimiter detected. The first byte picks the units and
// whether only the loading branch is kept. Problems go to the result's list; nothing throws.
#include "fabrics_db/import/tensile_import.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(tensile_import) {
  using namespace yarnfit;
  if (size == 0) return 0;
  const std::uint8_t choice = data[0];
  db::TensileImportOptions o;
  o.input = fuzz::input_file(fuzz::as_text(data + 1, size - 1), "export.csv");
  o.output = fuzz::scratch_folder() / "stretch.csv";
  o.extension = db::ColumnRef::parse("1");
  o.force = db::ColumnRef::parse("2");
  if (choice & 1) {
    o.extension_unit = db::ExtensionUnit::mm;
    o.gauge_length_mm = 100.0;
  }
  if (choice & 2) {
    o.width = db::ColumnRef::parse("3");
    o.swatch_width_mm = 50.0;
  }
  o.force_unit = (choice & 4) ? db::ForceUnit::cN : db::ForceUnit::N;
  o.loading_branch = (choice & 8) != 0;
  o.overwrite = true;
  const db::TensileImportResult r = db::import_tensile(o);
  if (r.written && !r.problems.empty()) fuzz::finding("nothing written when refused");
  return 0;
}
