#include "shell_fit/targets/uniform_targets.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "numerics/roots/bracketed_root.hpp"
#include "shell_fit/energies/inplane_material.hpp"

namespace yarnfit::shell {

namespace {

struct Frame {
  Eigen::Vector2d u, v;
};

Frame pull_frame(double angle) {
  return {Eigen::Vector2d(std::cos(angle), std::sin(angle)),
          Eigen::Vector2d(-std::sin(angle), std::cos(angle))};
}

Eigen::Matrix2d deformation(const Frame& f, double s, double c) {
  return (1.0 + s) * f.u * f.u.transpose() + (1.0 - c) * f.v * f.v.transpose();
}

// Ψ and dΨ/dc = −vᵀ P v along the line F(s, ·).
struct Slope {
  double psi = 0.0, d1 = 0.0;
};

Slope along_c(const InplaneMaterial& m, const Frame& f, double s, double c) {
  const Eigen::Matrix2d F = deformation(f, s, c);
  Slope out;
  out.psi = m.psi(F);
  if (!std::isfinite(out.psi)) return out;
  const Eigen::Matrix2d dF = -f.v * f.v.transpose();  // ∂F/∂c
  out.d1 = (m.pk1(F).array() * dF.array()).sum();
  return out;
}

}  // namespace

UniaxialPoint uniaxial_point(const InplaneParams& params, double pull_angle, double stretch,
                             double previous_c) {
  // The model lives in its material frame, so the pull angle is measured from the weft axis.
  const InplaneMaterial material(params, 0.0);
  const Frame f = pull_frame(pull_angle);
  UniaxialPoint out;
  out.stretch = stretch;

  // c* is the root of dΨ/dc, which increases with c (Ψ is convex along the line F(s, ·)) and
  // is +inf past c = 1, where the area barrier makes Ψ infinite (the width would vanish):
  // the root finder (numerics/roots) from the previous point's c* (continuation along s).
  const auto slope = [&](double c) -> std::optional<double> {
    const Slope sc = along_c(material, f, stretch, c);
    return std::isfinite(sc.psi) ? sc.d1 : std::numeric_limits<double>::infinity();
  };
  numerics::RootFindOptions ro;
  ro.lower = -10.0;
  ro.upper = 1.0;
  ro.initial_step = 0.05;
  ro.x_tolerance = 1e-13;
  ro.max_evaluations = 200;
  const double start = std::isfinite(along_c(material, f, stretch, previous_c).psi) ? previous_c : 0.0;
  const numerics::RootResult root = numerics::find_root(slope, start, ro);
  if (!root.converged() || !std::isfinite(root.f)) {
    out.compression = previous_c;
    out.converged = false;
    return out;
  }
  out.converged = true;
  const double c = root.x;
  out.compression = c;
  const Eigen::Matrix2d F = deformation(f, stretch, c);
  out.stress = f.u.dot(material.pk1(F) * f.u);
  if (!std::isfinite(out.stress)) {
    out.stress = 0.0;
    out.converged = false;
  }
  return out;
}

std::vector<DirectionTargets> generate_uniform_targets(const ShellParams& params,
                                                       const TargetRanges& ranges) {
  std::vector<DirectionTargets> all;
  for (const db::Direction d : db::k_all_directions) {
    const auto k = static_cast<std::size_t>(d);
    DirectionTargets t;
    t.direction = d;
    if (ranges.max_stretch[k] && ranges.stretch_samples > 1) {
      double c = 0.0;
      for (int i = 0; i < ranges.stretch_samples; ++i) {
        const double s = *ranges.max_stretch[k] * i / (ranges.stretch_samples - 1);
        const UniaxialPoint p = uniaxial_point(params.inplane, db::pull_angle(d), s, c);
        c = p.compression;
        t.stretch.push_back(p);
      }
    }
    if (ranges.max_curvature[k] && ranges.curvature_samples > 1) {
      const double kt = params.bending.ktheta[k];
      for (int i = 0; i < ranges.curvature_samples; ++i) {
        const double kappa = *ranges.max_curvature[k] * i / (ranges.curvature_samples - 1);
        t.bending.push_back({kappa, 2.0 * kt * kappa});
      }
    }
    if (!t.stretch.empty() || !t.bending.empty()) all.push_back(std::move(t));
  }
  return all;
}

}  // namespace yarnfit::shell
