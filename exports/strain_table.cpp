#include "exports/strain_table.hpp"

#include <cstdio>

#include <Eigen/Dense>

#include "shell_fit/energies/inplane_material.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::exports {

namespace {

constexpr double k_normal_from = -0.10, k_normal_to = 0.40, k_shear_to = 0.20, k_step = 0.05;
constexpr int k_uniaxial_points = 25;
constexpr double k_curvature_to = 50.0;
constexpr int k_curvature_points = 11;

int steps(double from, double to) { return static_cast<int>(std::lround((to - from) / k_step)); }

std::vector<StressRow> stress_rows(const shell::InplaneParams& law_params) {
  const shell::InplaneMaterial law(law_params, 0.0);
  std::vector<StressRow> rows;
  for (int i = 0; i <= steps(k_normal_from, k_normal_to); ++i)
    for (int j = 0; j <= steps(k_normal_from, k_normal_to); ++j)
      for (int k = 0; k <= steps(0.0, k_shear_to); ++k) {
        StressRow r{k_normal_from + i * k_step, k_normal_from + j * k_step, k * k_step};
        Eigen::Matrix2d G;
        G << r.e11, r.e12, r.e12, r.e22;
        // F = √(2E + I), the stretch without rotation; S = F⁻¹P.
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(2.0 * G + Eigen::Matrix2d::Identity());
        const Eigen::Matrix2d F = eig.operatorSqrt();
        const Eigen::Matrix2d S = F.inverse() * law.pk1(F);
        r.s11 = S(0, 0);
        r.s22 = S(1, 1);
        r.s12 = S(0, 1);
        r.psi = law.psi(F);
        rows.push_back(r);
      }
  return rows;
}

void add_shell_uniaxial(const FittedFabric& fabric, std::vector<UniaxialRow>& rows) {
  for (const db::Direction d : db::k_all_directions) {
    const double angle = db::pull_angle(d);
    const double end = fitted_range_end(fabric, angle);
    double c = 0.0;
    for (int i = 0; i < k_uniaxial_points && end > 0.0; ++i) {
      const db::UniaxialPoint p = shell::uniaxial_point(fabric.params.inplane, angle, end * i / (k_uniaxial_points - 1), c);
      if (!p.converged) break;
      c = p.compression;
      rows.push_back({"shell", std::string(db::to_string(d)), p.stretch, p.compression, p.stress});
    }
  }
}

// The yarn fit's final evaluation: S [N/m] is second Piola–Kirchhoff, the line force (1 + s) S.
void add_yarn_uniaxial(const results::YarnFitFile& yarn, std::vector<UniaxialRow>& rows) {
  for (const auto& curve : yarn.curves)
    for (std::size_t i = 0; i < curve.stretch.size() && i < curve.simulated_S_N_per_m.size(); ++i) {
      const double s = curve.stretch[i];
      const double c = i < curve.simulated_compression.size() ? curve.simulated_compression[i] : 0.0;
      rows.push_back({"yarn", curve.direction, s, c, (1.0 + s) * curve.simulated_S_N_per_m[i]});
    }
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

StrainTable strain_table(const FittedFabric& fabric) {
  StrainTable t;
  t.stress = stress_rows(fabric.params.inplane);
  add_shell_uniaxial(fabric, t.uniaxial);
  if (fabric.yarn) add_yarn_uniaxial(*fabric.yarn, t.uniaxial);
  else t.yarn_reason = "the yarn stage did not run in this folder (or failed): no yarn rows";
  for (const db::Direction d : db::k_all_directions) {
    const double kt = fabric.params.bending.ktheta[static_cast<std::size_t>(d)];
    for (int i = 0; i < k_curvature_points; ++i) {
      const double kappa = k_curvature_to * i / (k_curvature_points - 1);
      t.bending.push_back({std::string(db::to_string(d)), kappa, 2.0 * kt * kappa, kt * kappa * kappa});
    }
  }
  return t;
}

std::string stress_csv(const StrainTable& table) {
  std::string out = "e11,e22,e12,s11_N_per_m,s22_N_per_m,s12_N_per_m,psi_J_per_m2\n";
  for (const auto& r : table.stress)
    out += number(r.e11) + "," + number(r.e22) + "," + number(r.e12) + "," + number(r.s11) + "," + number(r.s22) + "," +
           number(r.s12) + "," + number(r.psi) + "\n";
  return out;
}

std::string uniaxial_csv(const StrainTable& table) {
  std::string out = "model,direction,stretch,compression,line_force_N_per_m\n";
  for (const auto& r : table.uniaxial)
    out += r.model + "," + r.direction + "," + number(r.stretch) + "," + number(r.compression) + "," +
           number(r.line_force) + "\n";
  return out;
}

std::string bending_csv(const StrainTable& table) {
  std::string out = "direction,curvature_per_m,moment_N,energy_J_per_m2\n";
  for (const auto& r : table.bending)
    out += r.direction + "," + number(r.curvature) + "," + number(r.moment) + "," + number(r.energy) + "\n";
  return out;
}

nlohmann::json table_json(const FittedFabric& fabric, const StrainTable& table) {
  nlohmann::json stress = nlohmann::json::array(), uniaxial = nlohmann::json::array(), bending = nlohmann::json::array();
  for (const auto& r : table.stress) stress.push_back({r.e11, r.e22, r.e12, r.s11, r.s22, r.s12, r.psi});
  for (const auto& r : table.uniaxial) uniaxial.push_back({r.model, r.direction, r.stretch, r.compression, r.line_force});
  for (const auto& r : table.bending) bending.push_back({r.direction, r.curvature, r.moment, r.energy});
  return {
      {"fabric", fabric.shell.fabric},
      {"shell_model", fabric.shell.model},
      {"fit_folder", fabric.folder.string()},
      {"stress",
       {{"columns", {"e11", "e22", "e12", "s11", "s22", "s12", "psi"}},
        {"units", {"-", "-", "-", "N/m", "N/m", "N/m", "J/m^2"}},
        {"grid",
         "material-frame Green strain, 1 = weft, 2 = warp: e11 and e22 from -0.10 to 0.40, e12 from 0 to 0.20, steps of "
         "0.05; s is the second Piola-Kirchhoff stress of the fitted shell law at F = sqrt(2E + I); s12 is odd in e12, "
         "s11, s22 and psi even"},
        {"rows", stress}}},
      {"uniaxial",
       {{"columns", {"model", "direction", "stretch", "compression", "line_force"}},
        {"units", {"", "", "-", "-", "N/m"}},
        {"grid",
         "a pull along the direction (weft 0, bias 45, warp 90 degrees from the weft), the width free (no stress across); "
         "shell: 25 stretches from 0 to the end of the fitted range; yarn: the fitted yarn model simulated on the tile at "
         "the yarn fit's target stretches (its final evaluation)"},
        {"rows", uniaxial},
        {"yarn_rows", table.yarn_reason.empty() ? nlohmann::json("present") : nlohmann::json(table.yarn_reason)}}},
      {"bending",
       {{"columns", {"direction", "curvature", "moment", "energy"}},
        {"units", {"", "1/m", "N", "J/m^2"}},
        {"grid", "the shell law's bending, energy k_theta kappa^2 per area, kappa from 0 to 50 1/m in 11 steps; the "
                 "direction is the one that bends (a weft strip curls along the weft)"},
        {"rows", bending}}}};
}

}  // namespace yarnfit::exports
