#pragma once
// A fitted fabric as a U3M 1.1 material (Browzwear and Vizoo's open format; the schemas are kept
// in exports/u3m_schemas/ with their licence and source): the material file `<fabric>.u3m` and
// the physics file `physics/physics.json` its `devices.fab` points at, as a folder or zipped
// into one `.u3ma`.
//
// The material carries no visual (front, back and side are null) and fills U3M's own physics
// fields where the record has them: weight [g/m²] from the areal density, the composition from
// the yarns' materials and mass fractions, material_type Knit, the construction from the knit
// (stockinette "Single jersey", rib1x1 "1 x 1 rib", rib2x2 "2 x 2 rib", others "other" with
// their name); thickness is null (no record states it). The physics file's raw_data is null
// (yarnfit holds no FAB measurement) and its `custom` section carries a block named yarnfit:
// the fitted shell law with units, the yarn parameters when that stage ran, the errors per
// direction and the provenance (record fingerprint, yarnfit version, the fit's options).

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "exports/fitted_fabric.hpp"

namespace yarnfit::exports {

struct U3mMaterial {
  std::string name;          // the fabric's id: `<name>.u3m`
  nlohmann::json material;   // the .u3m
  nlohmann::json physics;    // physics/physics.json
};

// A new material id (a random UUID v4 from OpenSSL's CSPRNG) and the time now, in UTC.
[[nodiscard]] U3mMaterial u3m_material(const FittedFabric& fabric);

// U3M's name for the construction of a knit or a family ("Single jersey", …), or empty when it
// has none (the material then says "other" with the name).
[[nodiscard]] std::string u3m_construction(const std::string& knit_or_family);

// The folder form: dir/<name>.u3m and dir/physics/physics.json, each written whole.
std::vector<std::filesystem::path> write_u3m_folder(const U3mMaterial& u3m, const std::filesystem::path& dir);
// The same two files zipped (stored, UTF-8 names) into `file`, written whole.
void write_u3ma(const U3mMaterial& u3m, const std::filesystem::path& file);

}  // namespace yarnfit::exports
