// Reading and checking fabric data: pyp tiles with their facts (R_est is the costly part,
// all segment pairs over the periodic copies) and a whole database of measured records.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "fabrics_db/records/database.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace {

namespace fs = std::filesystem;
const fs::path k_shared = YARNFIT_SHARED_DIR;

void tile_facts(benchmark::State& state, const std::string& name) {
  yarnfit::db::Problems problems;
  const auto tile = yarnfit::db::read_pyp(k_shared / "data/patterns" / name, problems);
  if (!tile) {
    state.SkipWithError(("cannot read " + name + ": " + problems.to_string()).c_str());
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(yarnfit::db::compute_tile_facts(*tile));
  state.counters["segments"] = tile->edge_count();
}

void read_tile(benchmark::State& state, const std::string& name) {
  for (auto _ : state) {
    yarnfit::db::Problems problems;
    benchmark::DoNotOptimize(yarnfit::db::read_pyp(k_shared / "data/patterns" / name, problems));
  }
}

void load_acrylic_database(benchmark::State& state) {
  const fs::path out = fs::temp_directory_path() / "yarnfit-bench-acrylic";
  fs::remove_all(out);
  const std::string cmd = "python3 '" + std::string(YARNFIT_SOURCE_DIR) +
                          "/scripts/build_acrylic_records.py' '" + out.string() + "' --shared '" +
                          k_shared.string() + "' >/dev/null";
  if (std::system(cmd.c_str()) != 0) {
    state.SkipWithError("could not build the acrylic records (is ../shared there?)");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(yarnfit::db::load_database(out));
  fs::remove_all(out);
}

}  // namespace

BENCHMARK_CAPTURE(read_tile, stockinette, "stockinette.pyp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_tile, cartridge_belt_rib, "cartridge_belt_rib.pyp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(tile_facts, stocktiniest, "stocktiniest.pyp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(tile_facts, stockinette, "stockinette.pyp")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(tile_facts, cartridge_belt_rib, "cartridge_belt_rib.pyp")->Unit(benchmark::kMillisecond);
BENCHMARK(load_acrylic_database)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
