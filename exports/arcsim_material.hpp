#pragma once
// A fitted shell law as ARCSim's material data file: Wang, Ramamoorthi & O'Brien 2011's
// data-driven model as ARCSim 0.3.1 reads it (conf.cpp load_material_data, dde.cpp; the format
// is described in docs/export_formats.md §1 and docs/exports.md).
//
// Stretching. ARCSim's stress at the Green strain G (material frame, u = weft) is the secant
//   S00 = k0 G00 + k1 G11,  S11 = k1 G00 + k2 G11,  S01 = ½ k3 G01,
// with K = (k0, k1, k2, k3) interpolated from the file's 6 rows: row 0 at rest, rows 1–5 at
// the largest principal stretch w = 7/6 with its direction at 0, 22.5, 45, 67.5 and 90° from
// the weft, linearly in (w − 1)·6 (held past 7/6) and in that angle; ARCSim doubles what the
// file holds. Row 0 is the law's own tangent at rest (drape lives at small strains); rows 1–5
// are the least-squares fit of that S to the law's S = F⁻¹P along the law's own uniaxial
// paths at 0, 5, …, 90° up to each angle's comfort stretch, residuals taken in the pull's
// frame (along and across the pull in full, the shear between them, which the law keeps at
// zero, at a tenth, so that it does not cost force), each path scaled by its largest stress
// and each row drawn weakly towards rest where the paths leave it free. So ARCSim's
// interpolation is matched where a garment works.
//
// Bending. ARCSim's energy per hinge edge is ke l² θ²/(8(A0 + A1)), ke interpolated from the
// file's 3 × 5 by the edge's direction (0, 45, 90° from the weft) and by α = θl/(2(A0 + A1))
// at 0, 5, …, 20 m⁻¹. The shell's is k_θ (θ/H)² (A0 + A1) with A0 + A1 = lH
// (shell_fit/energies/bending_term.hpp): the same, edge by edge on any mesh, when ke = 8 k_θ
// with k_θ that of the direction across the edge (an edge along the weft folds the warp). The
// law is linear in curvature, so the five columns are equal.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "exports/fitted_fabric.hpp"

namespace yarnfit::exports {

struct ArcsimMaterial {
  double density = 0.0;  // areal density [kg/m²]
  // As the file holds them (half of what ARCSim uses) [N/m]: row 0 at rest, rows 1–5 at the
  // largest principal stretch 7/6 along 0, 22.5, 45, 67.5, 90° from the weft; k0, k1, k2, k3.
  std::array<std::array<double, 4>, 6> stretching{};
  // ke [N·m] by hinge-edge direction (along the weft, the bias, the warp) and α = 0 … 20 m⁻¹.
  std::array<std::array<double, 5>, 3> bending{};
};

// The law of `fabric` sampled for ARCSim. Throws an Error without an areal density (ARCSim
// requires it: the record gives it).
[[nodiscard]] ArcsimMaterial arcsim_material(const FittedFabric& fabric);

// ARCSim's second Piola–Kirchhoff stress of `material` at the material-frame Green strain G
// [N/m], one sample of its stretching model evaluated as dde.cpp does, the direction of the
// largest principal stretch folded into [0°, 90°] (docs/exports.md: ARCSim itself does not fold).
[[nodiscard]] Eigen::Matrix2d arcsim_stress(const ArcsimMaterial& material, const Eigen::Matrix2d& G);

// The uniaxial line force [N/m] of a pull at `angle` [rad] from the weft to stretch s, the
// width free (zero stress across); from ARCSim's model, or from the fitted law.
struct UniaxialForce {
  double force = 0.0;
  double width_stretch = 1.0;  // 1 − c
  bool converged = false;
};
[[nodiscard]] UniaxialForce arcsim_uniaxial(const ArcsimMaterial& material, double angle, double stretch);

// How far ARCSim's uniaxial force strays from the law's over one tested direction's comfort
// range: mean and largest |difference| over 40 stretches, divided by the law's largest force.
struct ArcsimDeviation {
  std::string direction;
  double comfort_stretch = 0.0;
  double mean_pct = 0.0;  // NaN when ARCSim's model could not be followed
  double max_pct = 0.0;
};
[[nodiscard]] std::vector<ArcsimDeviation> arcsim_deviation(const FittedFabric& fabric, const ArcsimMaterial& material);
inline constexpr double k_arcsim_goal_pct = 3.0;

// The material file: density, stretching, bending, and a "yarnfit" block ARCSim does not read
// (the fit it came from, units, the deviations, what the format loses).
[[nodiscard]] nlohmann::json arcsim_json(const FittedFabric& fabric, const ArcsimMaterial& material,
                                         const std::vector<ArcsimDeviation>& deviation);

}  // namespace yarnfit::exports
