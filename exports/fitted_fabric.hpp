#pragma once
// What an export takes from a fit folder (a `yarnfit fit` output or a batch fabric folder):
// the fitted shell law of shell_fit.json, the yarn fit when that stage ran, and the figures of
// the record that the formats carry beside the law (areal density).
//
//   const exports::FittedFabric f = exports::read_fitted_fabric("out/demo", "examples/fabrics/stockinette_demo");
//   const shell::InplaneMaterial law(f.params.inplane, 0.0);

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "fabrics_db/records/fabric.hpp"
#include "numerics/util/error.hpp"
#include "results/shell_fit_file.hpp"
#include "results/yarn_fit_file.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/energies/inplane_material.hpp"

namespace yarnfit::exports {

struct FittedFabric {
  std::filesystem::path folder;
  results::ShellFitFile shell;  // shell_fit.json
  shell::InplaneModel model = shell::InplaneModel::thesis;
  shell::ShellParams params;  // the fitted law (absent lock-up terms are zero)
  std::optional<results::YarnFitFile> yarn;  // yarn_fit.json, when the yarn stage ran and succeeded
  std::string record;                        // the record folder, when given
  std::optional<db::Fabric> record_fabric;   // the record read, when given
  std::string record_sha256;                 // its fingerprint (db::fabric_hash), when given
  std::optional<double> areal_density;       // [kg/m²], from the record
};

// The fit in `fit_dir`; `record` (may be empty) is the fabric's record folder, read for its
// areal density. Throws an Error: no such folder, no shell_fit.json (with only yarn_fit.json:
// the yarn stage ran alone, so there is no shell law to export), a shell fit that failed, a
// record that cannot be read.
[[nodiscard]] FittedFabric read_fitted_fabric(const std::filesystem::path& fit_dir,
                                              const std::filesystem::path& record = {});

// The stretch up to which a format is held to the fitted law in `direction`: where the law's
// uniaxial line force reaches the comfort limit (33.3 N/m, SPEC §3), at most the end of that
// direction's fitted range.
[[nodiscard]] double comfort_stretch(const FittedFabric& fabric, const std::string& direction);
// The same along any pull angle [rad] from the weft, at most fitted_range_end(angle).
[[nodiscard]] double comfort_stretch_at(const FittedFabric& fabric, double angle);
// The end of the fitted stretch range along a pull angle [rad] from the weft: the tested
// directions' interpolated linearly in angle (held beyond the first and the last).
[[nodiscard]] double fitted_range_end(const FittedFabric& fabric, double angle);
// The law's second Piola–Kirchhoff stress [N/m] at the material-frame Green strain G: the
// stretch F = √(2G + I) without rotation, S = F⁻¹P(F).
[[nodiscard]] Eigen::Matrix2d law_stress(const shell::InplaneMaterial& law, const Eigen::Matrix2d& G);

inline constexpr double k_comfort_line_force = 2.0 / 0.06;  // 2 N on the thesis's 6 cm swatch [N/m]

}  // namespace yarnfit::exports
