#include "exports/arcsim_material.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Dense>

#include "numerics/roots/bracketed_root.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/energies/inplane_material.hpp"
#include "shell_fit/targets/uniform_targets.hpp"

namespace yarnfit::exports {

namespace {

constexpr int k_path_angles = 19;               // 0, 5, …, 90°
constexpr int k_path_points = 24;
constexpr double k_deg = std::numbers::pi / 180.0;
constexpr double k_pull_to_rest = 0.02;
constexpr double k_shear_weight = 0.1;

// Where a strain sits in ARCSim's table: the weight of the stretched level and the angle row
// (0…4) of the largest principal stretch with the weight of the next row.
struct TablePlace {
  double level = 0.0;
  int row = 0;
  double next = 0.0;
};

TablePlace table_place(const Eigen::Matrix2d& G) {
  const Eigen::Matrix2d C = 2.0 * G + Eigen::Matrix2d::Identity();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);  // ascending: column 1 is the largest
  const Eigen::Vector2d V = eig.eigenvectors().col(1);
  const double w = std::sqrt(std::max(eig.eigenvalues()(1), 0.0));
  double angle = std::abs(std::atan2(V(1), V(0))) / std::numbers::pi * 180.0;
  if (angle > 90.0) angle = 180.0 - angle;  // a principal direction is an axis
  TablePlace p;
  p.level = std::clamp((w - 1.0) * 6.0, 0.0, 1.0 - 1e-6);
  const double a = std::clamp(angle / 22.5, 0.0, 4.0 - 1e-6);
  p.row = static_cast<int>(a);
  p.next = a - p.row;
  return p;
}

// S = K G for K = (k0, k1, k2, k3).
Eigen::Matrix2d secant_stress(const std::array<double, 4>& k, const Eigen::Matrix2d& G) {
  Eigen::Matrix2d S;
  S(0, 0) = k[0] * G(0, 0) + k[1] * G(1, 1);
  S(1, 1) = k[1] * G(0, 0) + k[2] * G(1, 1);
  S(0, 1) = S(1, 0) = 0.5 * k[3] * G(0, 1);
  return S;
}

Eigen::Vector2d along(double angle) { return {std::cos(angle), std::sin(angle)}; }
Eigen::Vector2d across(double angle) { return {-std::sin(angle), std::cos(angle)}; }

Eigen::Matrix2d pull(double angle, double stretch, double width_stretch) {
  const Eigen::Vector2d u = along(angle), v = across(angle);
  return (1.0 + stretch) * u * u.transpose() + width_stretch * v * v.transpose();
}

Eigen::Matrix2d green(const Eigen::Matrix2d& F) {
  return 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
}

// One state of the law on its uniaxial path: Green strain and S = F⁻¹P.
struct LawState {
  Eigen::Matrix2d G, S;
};

// The law's uniaxial path at `angle` up to `end`, k_path_points states.
std::vector<LawState> law_path(const shell::InplaneParams& law, double angle, double end) {
  const shell::InplaneMaterial material(law, 0.0);
  std::vector<LawState> path;
  double c = 0.0;
  for (int i = 1; i <= k_path_points; ++i) {
    const db::UniaxialPoint p = shell::uniaxial_point(law, angle, end * i / k_path_points, c);
    if (!p.converged) break;
    c = p.compression;
    const Eigen::Matrix2d F = pull(angle, p.stretch, 1.0 - c);
    path.push_back({green(F), F.inverse() * material.pk1(F)});
  }
  return path;
}

// ARCSim's row 0: the law's tangent at rest, by central differences of S (k3 on G01: S01 = ½k3 G01).
std::array<double, 4> rest_stiffness(const shell::InplaneParams& params) {
  const shell::InplaneMaterial law(params, 0.0);
  constexpr double h = 1e-6;
  const auto dS = [&](int i, int j) {
    Eigen::Matrix2d G = Eigen::Matrix2d::Zero();
    G(i, j) = G(j, i) = h;
    return Eigen::Matrix2d((law_stress(law, G) - law_stress(law, -G)) / (2 * h));
  };
  const Eigen::Matrix2d along_weft = dS(0, 0), along_warp = dS(1, 1), shear = dS(0, 1);
  return {along_weft(0, 0), along_weft(1, 1), along_warp(1, 1), 2.0 * shear(0, 1)};
}

// One least-squares equation in the 24 stiffnesses (ARCSim's: row 0, then rows 1–5).
struct Equation {
  Eigen::Matrix<double, 1, 24> row = Eigen::Matrix<double, 1, 24>::Zero();
  double rhs = 0.0;
};

// The residuals of one state of a path at `angle`, ARCSim's S against the law's, in the pull's
// frame: along, across (both what a uniaxial test sees: the force and the free width) and the
// shear between them, which the law keeps at zero and which is weighted down (k_shear_weight) so
// that it does not cost force. `scale` makes paths of different stiffness count alike.
std::array<Equation, 3> state_equations(const LawState& st, double angle, double scale) {
  const TablePlace p = table_place(st.G);
  // K = (1 − level) K_rest + level ((1 − next) K_row + next K_row+1), row 5 the last.
  const std::array<std::pair<int, double>, 3> blocks{
      {{0, 1.0 - p.level}, {1 + p.row, p.level * (1.0 - p.next)}, {std::min(2 + p.row, 5), p.level * p.next}}};
  const double G00 = st.G(0, 0), G11 = st.G(1, 1), G01 = st.G(0, 1);
  // ∂(S00, S11, S01)/∂(k0, k1, k2, k3) of S = K G.
  const std::array<std::array<double, 4>, 3> dS{{{G00, G11, 0, 0}, {0, G00, G11, 0}, {0, 0, 0, 0.5 * G01}}};
  const Eigen::Vector2d u = along(angle), v = across(angle);
  // (along, across, shear) as combinations of (S00, S11, S01).
  const std::array<std::array<double, 3>, 3> frame{{{u(0) * u(0), u(1) * u(1), 2 * u(0) * u(1)},
                                                    {v(0) * v(0), v(1) * v(1), 2 * v(0) * v(1)},
                                                    {u(0) * v(0), u(1) * v(1), u(0) * v(1) + u(1) * v(0)}}};
  const std::array<double, 3> weight{1.0, 1.0, k_shear_weight};
  const std::array<double, 3> law{st.S(0, 0), st.S(1, 1), st.S(0, 1)};
  std::array<Equation, 3> out;
  for (std::size_t f = 0; f < 3; ++f) {
    const double w = weight[f] / scale;
    for (std::size_t c = 0; c < 3; ++c) {
      for (const auto& [block, share] : blocks)
        for (std::size_t k = 0; k < 4; ++k) out[f].row(4 * block + static_cast<int>(k)) += w * frame[f][c] * share * dS[c][k];
      out[f].rhs += w * frame[f][c] * law[c];
    }
  }
  return out;
}

// The 24 stiffnesses (ARCSim's, twice the file's): row 0 the law's at rest, rows 1–5 by least
// squares over the law's uniaxial paths.
Eigen::Matrix<double, 24, 1> fit_stretching(const FittedFabric& fabric) {
  std::vector<Equation> equations;
  double scale_all = 1.0;
  for (int j = 0; j < k_path_angles; ++j) {
    const double angle = 5.0 * j * k_deg;
    const std::vector<LawState> path = law_path(fabric.params.inplane, angle, comfort_stretch_at(fabric, angle));
    double scale = 0.0;
    for (const auto& st : path) scale = std::max(scale, st.S.cwiseAbs().maxCoeff());
    if (scale <= 0.0) continue;
    scale_all = std::max(scale_all, scale);
    for (const auto& st : path)
      for (const Equation& e : state_equations(st, angle, scale)) equations.push_back(e);
  }
  // The paths say little of some entries (the stiffness across a weft pull, where the stress
  // across is zero): each stretched row is drawn weakly towards the rest row, as a strain of
  // k_pull_to_rest would weigh it, so that ARCSim keeps a stiffness across every pull.
  for (int r = 1; r < 6; ++r)
    for (int k = 0; k < 4; ++k) {
      Equation e;
      e.row(4 * r + k) = k_pull_to_rest / scale_all;
      e.row(k) = -k_pull_to_rest / scale_all;
      equations.push_back(e);
    }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(equations.size()), 24);
  Eigen::VectorXd b(static_cast<Eigen::Index>(equations.size()));
  for (std::size_t i = 0; i < equations.size(); ++i) {
    A.row(static_cast<Eigen::Index>(i)) = equations[i].row;
    b(static_cast<Eigen::Index>(i)) = equations[i].rhs;
  }
  // Row 0 is the law's at rest; the stretched rows take what remains (a row no path reaches
  // stays at rest, through the pull towards it).
  const std::array<double, 4> rest = rest_stiffness(fabric.params.inplane);
  const Eigen::Vector4d k0(rest[0], rest[1], rest[2], rest[3]);
  Eigen::Matrix<double, 24, 1> k;
  k << k0, A.rightCols(20).completeOrthogonalDecomposition().solve(b - A.leftCols(4) * k0);
  return k;
}

}  // namespace

ArcsimMaterial arcsim_material(const FittedFabric& fabric) {
  if (!fabric.areal_density)
    throw Error(ErrorCategory::input, fabric.folder.string() + ": ARCSim needs the areal density: " +
                      (fabric.record.empty() ? std::string("give the fabric's record (--record) or --areal-density-gsm")
                                             : fabric.record + " has no areal_density_gsm: give --areal-density-gsm"));
  ArcsimMaterial m;
  m.density = *fabric.areal_density;
  const Eigen::Matrix<double, 24, 1> k = fit_stretching(fabric);
  for (std::size_t r = 0; r < 6; ++r)
    for (std::size_t c = 0; c < 4; ++c) m.stretching[r][c] = 0.5 * k(static_cast<Eigen::Index>(4 * r + c));
  // Rows by hinge-edge direction: along the weft it folds the warp, along the warp the weft.
  const auto& kt = fabric.params.bending.ktheta;
  const std::array<double, 3> by_edge{kt[2], kt[1], kt[0]};
  for (std::size_t r = 0; r < 3; ++r) m.bending[r].fill(8.0 * by_edge[r]);
  return m;
}

Eigen::Matrix2d arcsim_stress(const ArcsimMaterial& material, const Eigen::Matrix2d& G) {
  const TablePlace p = table_place(G);
  std::array<double, 4> k{};
  const auto& d = material.stretching;
  for (std::size_t i = 0; i < 4; ++i) {
    const double stretched = (1.0 - p.next) * d[1 + static_cast<std::size_t>(p.row)][i] + p.next * d[2 + static_cast<std::size_t>(p.row)][i];
    k[i] = 2.0 * std::max(0.0, (1.0 - p.level) * d[0][i] + p.level * stretched);
  }
  return secant_stress(k, G);
}

UniaxialForce arcsim_uniaxial(const ArcsimMaterial& material, double angle, double stretch) {
  const Eigen::Vector2d u = along(angle), v = across(angle);
  // The stress across the pull grows with the width kept: its zero is the free width.
  const auto across_stress = [&](double width) -> std::optional<double> {
    return v.dot(arcsim_stress(material, green(pull(angle, stretch, width))) * v);
  };
  numerics::RootFindOptions o;
  o.lower = 0.05;
  o.upper = 1.5;
  o.initial_step = 0.02;
  o.x_tolerance = 1e-12;
  o.max_evaluations = 200;
  const numerics::RootResult root = numerics::find_root(across_stress, 1.0, o);
  UniaxialForce out;
  out.converged = root.converged();
  out.width_stretch = root.x;
  const Eigen::Matrix2d F = pull(angle, stretch, root.x);
  out.force = u.dot(F * arcsim_stress(material, green(F)) * u);
  return out;
}

std::vector<ArcsimDeviation> arcsim_deviation(const FittedFabric& fabric, const ArcsimMaterial& material) {
  std::vector<ArcsimDeviation> out;
  constexpr int points = 40;
  for (const auto& d : fabric.shell.directions) {
    const auto dir = db::parse_direction(d.direction);
    if (!dir) continue;
    ArcsimDeviation dev;
    dev.direction = d.direction;
    dev.comfort_stretch = comfort_stretch(fabric, d.direction);
    double sum = 0.0, largest = 0.0, worst = 0.0, c = 0.0;
    bool followed = dev.comfort_stretch > 0.0;
    for (int i = 1; i <= points && followed; ++i) {
      const double s = dev.comfort_stretch * i / points;
      const db::UniaxialPoint law = shell::uniaxial_point(fabric.params.inplane, db::pull_angle(*dir), s, c);
      const UniaxialForce arcsim = arcsim_uniaxial(material, db::pull_angle(*dir), s);
      c = law.compression;
      followed = law.converged && arcsim.converged;
      sum += std::abs(arcsim.force - law.stress);
      worst = std::max(worst, std::abs(arcsim.force - law.stress));
      largest = std::max(largest, std::abs(law.stress));
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    dev.mean_pct = followed && largest > 0.0 ? 100.0 * sum / points / largest : nan;
    dev.max_pct = followed && largest > 0.0 ? 100.0 * worst / largest : nan;
    out.push_back(dev);
  }
  return out;
}

nlohmann::json arcsim_json(const FittedFabric& fabric, const ArcsimMaterial& material,
                           const std::vector<ArcsimDeviation>& deviation) {
  nlohmann::json deviations = nlohmann::json::object();
  for (const auto& d : deviation)
    deviations[d.direction] = {{"comfort_range_end", d.comfort_stretch},
                               {"mean_pct", d.mean_pct},
                               {"max_pct", d.max_pct},
                               {"within_goal", std::isfinite(d.mean_pct) && d.mean_pct <= k_arcsim_goal_pct}};
  return {
      {"density", material.density},
      {"stretching", material.stretching},
      {"bending", material.bending},
      {"yarnfit",
       {{"format", "ARCSim 0.3.1 material data (Wang, Ramamoorthi & O'Brien 2011); ARCSim reads density, "
                   "stretching and bending and ignores this block"},
        {"fabric", fabric.shell.fabric},
        {"family", fabric.shell.family},
        {"shell_model", fabric.shell.model},
        {"fit_folder", fabric.folder.string()},
        {"record", fabric.record},
        {"units", {{"density", "kg/m^2"}, {"stretching", "N/m (ARCSim uses twice the value)"}, {"bending", "N m"}}},
        {"deviation_goal_pct", k_arcsim_goal_pct},
        {"uniaxial_deviation", deviations},
        {"lost",
         {"the law between rest and stretch 7/6 is linear interpolation of a secant stiffness, and past 7/6 the "
          "stiffness is held: a lock-up that grows further is not carried",
          "the area (Neo-Hookean) terms enter only through the fitted secant stiffnesses",
          "ARCSim reads the direction of the largest principal stretch without folding it into [0, 90] degrees, "
          "so for some states it uses the 90-degree row"}}}}};
}

}  // namespace yarnfit::exports
