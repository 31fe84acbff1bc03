// The fabric record (SPEC §2): fabric.yaml with the CSVs and tile it names, as one input split
// into files (fuzz_support.hpp). load_fabric reports every problem in its list and never
// throws.
#include "fabrics_db/records/fabric_reader.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(fabric_record) {
  using namespace yarnfit;
  const std::filesystem::path folder = fuzz::fresh_folder("record");
  for (const auto& [name, text] : fuzz::split_files(fuzz::as_text(data, size), "fabric.yaml"))
    fuzz::write_bytes(folder / name, text);
  const db::FabricLoad load = db::load_fabric(folder);
  if (load.fabric && !load.problems.empty()) fuzz::finding("a record is whole or absent");
  return 0;
}
