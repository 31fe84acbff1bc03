#pragma once
// Reading a Browzwear FAB measurement from U3M 1.1 (issue 51; docs/fab.md): the physics file
// (`raw_data`: grains L, W, B with tests S1, S2, U1, D1, D2, mass per area M, thickness
// test T), a `.u3m` material that names one under material.physics.devices.fab, or a
// `.u3ma` archive holding both. Units are converted to SI (cm → m, grams-force → N, g/m² →
// kg/m²; the thickness test's cm → m); the grains map to yarnfit's directions (length → warp, width → weft, bias
// → bias). Every problem names the file and the JSON path (`/raw_data/L/S2/samplesTree/3`);
// the vendor's `custom` block is read leniently (numbers there come either as numbers or as
// text).

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/records/fab_test.hpp"
#include "fabrics_db/records/fabric.hpp"

namespace yarnfit::db {

inline constexpr double k_gram_force = 9.80665e-3;  // [N]

// FAB grain letter → yarnfit direction: L → warp, W → weft, B → bias.
std::optional<Direction> fab_grain_direction(char grain);
char fab_grain_letter(Direction d);

struct FabMeasurement {
  std::string label;  // the file as the user named it ("x.u3ma!physics/physics.json" inside an archive)
  std::map<Direction, std::vector<FabTest>> tests;  // per direction, in protocol order
  double mass_per_area = 0.0;        // [kg/m²]
  std::optional<double> thickness;   // [m], the thickness test's first contact distance
  std::optional<long long> serial, hardware_version, build;
  std::string name, category, composition;  // from custom.browzwear, when given
  std::string physics_text;  // the physics file's bytes, unchanged (kept beside the record)
};

struct FabRead {
  std::optional<FabMeasurement> measurement;  // present only when problems is empty
  Problems problems;
};

// A physics document given as text; `label` names it in problems.
FabRead parse_fab_physics(std::string_view text, const std::string& label);
// A file: .json (the physics file), .u3m (a material naming one) or .u3ma (an archive).
FabRead read_fab_file(const std::filesystem::path& file);

// The load cell's zero from a stretch test: the median reading over the samples, of every
// branch, where the strip is slack (clamp distance at least 0.5 % below its taut length, the
// file's `length`); nullopt when fewer than 3 samples are slack. A bend's strip is looped from
// its first sample, so no sample of it reads zero load and none is estimated.
struct ZeroOffset {
  double value = 0.0;
  int samples = 0;
};
std::optional<ZeroOffset> estimate_zero_offset(const FabTest& test);

}  // namespace yarnfit::db
