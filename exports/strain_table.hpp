#pragma once
// The homogenised response of a fitted fabric as tables a simulator can interpolate
// (docs/exports.md says how):
//  * stress: the shell law's second Piola–Kirchhoff stress and energy density on a grid of
//    material-frame Green strain, E11 (weft) and E22 (warp) from −0.10 to 0.40 and E12 from 0
//    to 0.20, steps of 0.05 (S12 is odd in E12, S11, S22 and ψ even);
//  * uniaxial: pulls along the weft, the bias and the warp with the width free, the line force
//    and the compression across, from the shell law (25 stretches to the end of the fitted
//    range) and, when the yarn stage ran, from the fitted yarn model simulated on the tile at
//    the yarn fit's target stretches (its final evaluation, yarn_fit.json's curves);
//  * bending: the shell law's moment 2 k_θ κ and energy k_θ κ² per direction, κ = 0 … 50 m⁻¹,
//    and, when the yarn stage ran and the tile is at hand (the record's, or a knit's generated
//    tile in `tile_cache`), the fitted yarn model's moment ∂Ψ/∂κ and energy simulated on the
//    tile (its rest shape first, as `yarn sim --curvature` does) at κ = 0, 10, … 50 m⁻¹.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "exports/fitted_fabric.hpp"

namespace yarnfit::exports {

struct StressRow {
  double e11 = 0, e22 = 0, e12 = 0;  // Green strain, material frame (weft = 1)
  double s11 = 0, s22 = 0, s12 = 0;  // second Piola–Kirchhoff stress [N/m]
  double psi = 0;                    // energy density [J/m²]
};

struct UniaxialRow {
  std::string model;      // shell or yarn
  std::string direction;  // weft, bias, warp
  double stretch = 0;     // s = l/l0 − 1
  double compression = 0;  // c = 1 − w/w0, the width free
  double line_force = 0;   // first Piola–Kirchhoff stress along the pull [N/m]
};

struct BendingRow {
  std::string model;  // shell or yarn
  std::string direction;
  double curvature = 0;  // [1/m]
  double moment = 0;     // ∂ψ/∂κ [N]
  double energy = 0;     // ψ [J/m²]
};

struct StrainTable {
  std::vector<StressRow> stress;
  std::vector<UniaxialRow> uniaxial;
  std::vector<BendingRow> bending;
  std::string yarn_reason;          // why there are no yarn uniaxial rows; empty when there are
  std::string yarn_bending_reason;  // why there are no yarn bending rows; empty when there are
};

// `tile_cache`: where the fit kept a knit's generated tile (the fit folder for `fit`, the
// batch's tiles/ for a batch); unused for a record that names its tile.
[[nodiscard]] StrainTable strain_table(const FittedFabric& fabric, const std::filesystem::path& tile_cache = {});

// The files of the table: stress.csv, uniaxial.csv, bending.csv, and table.json with all
// three, the units, the grids and where the rows come from.
[[nodiscard]] std::string stress_csv(const StrainTable& table);
[[nodiscard]] std::string uniaxial_csv(const StrainTable& table);
[[nodiscard]] std::string bending_csv(const StrainTable& table);
[[nodiscard]] nlohmann::json table_json(const FittedFabric& fabric, const StrainTable& table);

}  // namespace yarnfit::exports
