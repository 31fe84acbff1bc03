#include "shell_fit/targets/uniform_targets.hpp"

#include <cmath>

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

// dΨ/dc = −vᵀ P v and d²Ψ/dc² = vᵀ⊗vᵀ : ∂P/∂F : v⊗v, both along the line F(s, ·).
struct Slope {
  double psi = 0.0, d1 = 0.0, d2 = 0.0;
};

Slope along_c(const InplaneMaterial& m, const Frame& f, double s, double c) {
  const Eigen::Matrix2d F = deformation(f, s, c);
  Slope out;
  out.psi = m.psi(F);
  if (!std::isfinite(out.psi)) return out;
  const Eigen::Matrix2d dF = -f.v * f.v.transpose();  // ∂F/∂c
  const Eigen::Matrix2d P = m.pk1(F);
  out.d1 = (P.array() * dF.array()).sum();
  const Eigen::Matrix4d A = m.dpk1(F);
  const Eigen::Map<const Eigen::Vector4d> w(dF.data());
  out.d2 = w.dot(A * w);
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

  // Safeguarded Newton on dΨ/dc = 0 inside a bracket [lo, hi] with dΨ/dc(lo) < 0 < dΨ/dc(hi).
  // c < 1 always (the width stays positive); the area barrier makes Ψ → ∞ as c → 1.
  auto at = [&](double c) { return along_c(material, f, stretch, c); };
  double lo = previous_c, hi = previous_c;
  double step = 0.05;
  Slope s_lo = at(lo);
  if (!std::isfinite(s_lo.psi)) {
    lo = hi = 0.0;
    s_lo = at(0.0);
  }
  Slope s_hi = s_lo;
  // Expand the bracket: more compression while the slope is negative, less while positive.
  for (int i = 0; i < 200 && s_lo.d1 > 0.0; ++i) {
    hi = lo;
    s_hi = s_lo;
    lo -= step;
    step *= 1.6;
    s_lo = at(lo);
  }
  step = 0.05;
  for (int i = 0; i < 200 && !(s_hi.d1 > 0.0); ++i) {
    lo = hi;
    s_lo = s_hi;
    double next = hi + step;
    if (next >= 1.0) next = 0.5 * (hi + 1.0);  // approach the barrier, never cross it
    step *= 1.6;
    hi = next;
    s_hi = at(hi);
    if (!std::isfinite(s_hi.psi)) s_hi.d1 = 1.0;  // past the barrier counts as "rising"
  }
  if (!(s_lo.d1 <= 0.0 && s_hi.d1 > 0.0)) {
    out.compression = previous_c;
    out.converged = false;
    return out;
  }
  double c = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const Slope sc = at(c);
    if (!std::isfinite(sc.psi)) {
      hi = c;
    } else if (sc.d1 > 0.0) {
      hi = c;
    } else {
      lo = c;
    }
    double next = (std::isfinite(sc.psi) && sc.d2 > 0.0) ? c - sc.d1 / sc.d2 : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    if (std::abs(next - c) < 1e-13 || hi - lo < 1e-13) {
      c = next;
      out.converged = true;
      break;
    }
    c = next;
  }
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
