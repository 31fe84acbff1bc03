#pragma once
// The bundled example record (examples/fabrics/stockinette_demo) for tests that drive the
// fits from code, and a reduced copy whose shell stage takes about a second.
#include <gtest/gtest.h>

#include <filesystem>

#include "fabrics_db/records/fabric_reader.hpp"

namespace yarnfit::testing {

inline std::filesystem::path bundled_example_folder() {
  return std::filesystem::path(YARNFIT_SOURCE_DIR) / "examples/fabrics/stockinette_demo";
}

// Its tile (the stitch-by-stitch acrylic stockinette).
inline const std::filesystem::path k_example_tile = bundled_example_folder() / "tile.pyp";

inline db::Fabric bundled_example() {
  const auto load = db::load_fabric(bundled_example_folder());
  EXPECT_TRUE(load.ok()) << load.problems.to_string();
  return load.fabric ? *load.fabric : db::Fabric{};
}

// The example with its weft stretch test only (no bias, warp or bending test).
inline db::Fabric weft_only_example() {
  db::Fabric f = bundled_example();
  f.stretch_tests.erase(db::Direction::bias);
  f.stretch_tests.erase(db::Direction::warp);
  f.bending_tests.clear();
  return f;
}

}  // namespace yarnfit::testing
