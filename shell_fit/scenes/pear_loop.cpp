#include "shell_fit/scenes/pear_loop.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "numerics/roots/bracketed_root.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/energies/bending_term.hpp"
#include "shell_fit/energies/gravity_term.hpp"
#include "shell_fit/energies/membrane_term.hpp"
#include "shell_fit/mesh/rect_mesh.hpp"
#include "numerics/util/index.hpp"

namespace yarnfit::shell {

namespace {

using std::numbers::pi;

// B = 2 k_θ (pear_loop.hpp).
constexpr double k_bending_factor = 2.0;

using numerics::idx;

// The left half of the start loop, sampled at `segments` equal arc steps of S/segments:
// positions relative to the left clamp (x right, z up), the strip leaving it straight down.
struct HalfLoop {
  std::vector<double> x, z;  // segments + 1 points, x[0] = z[0] = 0
  double ds = 0.0;
};

HalfLoop half_loop(double half_length, double a, int segments) {
  HalfLoop h;
  h.ds = half_length / segments;
  h.x.assign(idx(segments + 1), 0.0);
  h.z.assign(idx(segments + 1), 0.0);
  for (int i = 0; i < segments; ++i) {
    // Each chord takes the tangent at its midpoint: exactly isometric, second-order accurate.
    const double t = (i + 0.5) / segments;
    const double theta = -pi / 2 + (pi / 2) * t - a * std::sin(pi * t);
    h.x[idx(i + 1)] = h.x[idx(i)] + h.ds * std::cos(theta);
    h.z[idx(i + 1)] = h.z[idx(i)] + h.ds * std::sin(theta);
  }
  return h;
}

// The extreme (min when sign = +1, max when sign = −1) of f along a line of evenly spaced
// samples, refined by the parabola through the extreme sample and its neighbours. `weights`
// receives (index, ∂extreme/∂f_index) for the samples used.
double parabolic_extreme(const std::vector<double>& f, double sign,
                         std::vector<std::pair<int, double>>& weights) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(f.size()); ++i)
    if (sign * f[idx(i)] < sign * f[idx(best)]) best = i;
  weights.clear();
  const int n = static_cast<int>(f.size());
  if (best > 0 && best < n - 1) {
    const double fm = f[idx(best - 1)], f0 = f[idx(best)], fp = f[idx(best + 1)];
    if (sign * fm > sign * f0 && sign * fp > sign * f0) {
      // Vertex of the parabola: e = f0 − (fp − fm)²/(8c), c = fp − 2 f0 + fm (c ≠ 0 here).
      const double a = fp - fm, c = fp - 2.0 * f0 + fm;
      const double e = f0 - a * a / (8.0 * c);
      weights = {{best - 1, a / (4.0 * c) + a * a / (8.0 * c * c)},
                 {best, 1.0 - a * a / (4.0 * c * c)},
                 {best + 1, -a / (4.0 * c) + a * a / (8.0 * c * c)}};
      return e;
    }
  }
  weights = {{best, 1.0}};
  return f[idx(best)];
}

// x and z of the centre line's vertices (by rest x) in the state x.
struct CentreLine {
  std::vector<double> x, z;
};

CentreLine centre_line_of(const Eigen::VectorXd& x, const std::vector<int>& vertices) {
  CentreLine out;
  for (int v : vertices) {
    out.x.push_back(x[BendingTerm::dim * v]);
    out.z.push_back(x[BendingTerm::dim * v + 2]);
  }
  return out;
}

}  // namespace

double bending_stiffness_per_width(double ktheta_effective) { return k_bending_factor * ktheta_effective; }

double bending_length(double ktheta_effective, double areal_density, double g) {
  return std::cbrt(bending_stiffness_per_width(ktheta_effective) / (areal_density * g));
}

double ktheta_for_bending_length(double length, double areal_density, double g) {
  return areal_density * g * length * length * length / k_bending_factor;
}

PearLoopScene::PearLoopScene(const PearLoopSetup& setup) : m_setup(setup) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(setup.length) || !positive(setup.width))
    throw Error(ErrorCategory::input, "pear loop: length and width must be positive and finite");
  if (!std::isfinite(setup.areal_density) || setup.areal_density < 0.0 || !std::isfinite(setup.gravity) ||
      setup.gravity < 0.0)
    throw Error(ErrorCategory::input, "pear loop: areal density and gravity must be finite and ≥ 0");
  if (!std::isfinite(setup.material_angle))
    throw Error(ErrorCategory::input, "pear loop: material angle must be finite");
  int n = setup.cells_along;
  if (n == 0) {
    if (!positive(setup.target_edge)) throw Error(ErrorCategory::input, "pear loop: target_edge must be positive");
    n = std::max(2, 2 * static_cast<int>(std::lround(0.5 * setup.length / setup.target_edge)));
  }
  if (n < 2 || n % 2 != 0) throw Error(ErrorCategory::input, "pear loop: cells_along must be even and ≥ 2");
  int n_across = setup.cells_across;
  if (n_across == 0) n_across = std::max(2, 2 * static_cast<int>(std::lround(0.5 * setup.width * n / setup.length)));
  if (n_across < 2 || n_across % 2 != 0)
    throw Error(ErrorCategory::input, "pear loop: cells_across must be even and ≥ 2");
  if (setup.refinements < 0) throw Error(ErrorCategory::input, "pear loop: refinements must be ≥ 0");

  m_clamp = setup.length / n;
  m_mesh = make_rect_mesh(setup.length + 2.0 * m_clamp, setup.width, n + 2, n_across,
                          setup.material_angle);
  for (int r = 0; r < setup.refinements; ++r) m_mesh = refine(m_mesh);

  const double tol = 1e-9 * setup.length;
  const auto clamped = vertices_where(m_mesh, [&](const Eigen::Vector2d& p) {
    return p.x() <= m_clamp + tol || p.x() >= setup.length + m_clamp - tol;
  });
  m_fixed_dofs = vertex_dofs(clamped, BendingTerm::dim);
  m_centre_line = vertices_at_y(m_mesh, 0.0, tol);

  // The loop bends the edges across the strip (rest direction along y); the others stay flat.
  const BendingTerm probe(m_mesh, BendingParams{});
  for (int i = 0; i < static_cast<int>(probe.edges().size()); ++i) {
    const auto& e = probe.edges()[idx(i)];
    const Eigen::Vector2d d = m_mesh.rest.row(e.v[1]) - m_mesh.rest.row(e.v[0]);
    if (std::abs(d.x()) > tol) continue;
    m_across_edges.push_back(i);
    const double w = e.area / (e.rest_height * e.rest_height);
    for (int j = 0; j < 3; ++j) m_governing[j] += w * e.weights[idx(j)];
  }
  if (m_governing.sum() > 0.0) m_governing /= m_governing.sum();
}

int PearLoopScene::governing_ktheta() const {
  int best = 0;
  m_governing.maxCoeff(&best);
  return best;
}

double PearLoopScene::effective_ktheta(const BendingParams& p) const {
  return m_governing[0] * p.ktheta[0] + m_governing[1] * p.ktheta[1] + m_governing[2] * p.ktheta[2];
}

Eigen::VectorXd PearLoopScene::initial_state(double clamp_distance) const {
  const double L = m_setup.length, S = 0.5 * L, d = clamp_distance;
  if (!std::isfinite(d) || d < 0.0) throw Error(ErrorCategory::input, "pear loop: clamp distance must be finite and ≥ 0");
  constexpr int segments = 2000;
  // ∫₀^S cos θ ds decreases with a while θ stays in (−π, 0) (a ∈ [−0.5, 1.5]: the loop goes
  // from a wide U, d ≈ 0.8 L, to a pear whose ends cross, d < 0).
  constexpr double lo = -0.5, hi = 1.5;
  const auto misses = [&](double a) { return 0.5 * d - half_loop(S, a, segments).x.back(); };  // increasing in a
  if (misses(lo) > 0.0 || misses(hi) < 0.0)
    throw Error(ErrorCategory::input, "pear loop: no loop of length " + std::to_string(L) + " m closes at clamp distance " +
                                std::to_string(d) + " m");
  numerics::RootFindOptions ro;
  ro.lower = lo;
  ro.upper = hi;
  ro.initial_step = 0.25;
  ro.x_tolerance = 1e-14;
  ro.max_evaluations = 200;
  const numerics::RootResult bulge =
      numerics::find_root([&](double a) -> std::optional<double> { return misses(a); }, 0.5 * (lo + hi), ro);
  const HalfLoop h = half_loop(S, bulge.x, segments);
  const auto at = [&](double s, double& x, double& z) {
    // s ∈ [0, S] along the left half, linear between the samples.
    const double u = std::clamp(s / h.ds, 0.0, static_cast<double>(segments));
    const int i = std::min(static_cast<int>(u), segments - 1);
    const double t = u - i;
    x = (1.0 - t) * h.x[idx(i)] + t * h.x[idx(i + 1)];
    z = (1.0 - t) * h.z[idx(i)] + t * h.z[idx(i + 1)];
  };

  Eigen::VectorXd x(BendingTerm::dim * m_mesh.vertex_count());
  for (int v = 0; v < m_mesh.vertex_count(); ++v) {
    const double X = m_mesh.rest(v, 0), Y = m_mesh.rest(v, 1);
    const double s = X - m_clamp;  // arc length from the left clamp
    double px = 0.0, pz = 0.0;
    if (s <= 0.0) {
      px = -0.5 * d;
      pz = -s;
    } else if (s >= L) {
      px = 0.5 * d;
      pz = s - L;
    } else if (s <= S) {
      at(s, px, pz);
      px -= 0.5 * d;
    } else {
      at(L - s, px, pz);
      px = 0.5 * d - px;
    }
    x.segment<3>(BendingTerm::dim * v) << px, Y, pz;
  }
  return x;
}

PearLoopScene::Shape PearLoopScene::measure(const Eigen::VectorXd& x) const {
  const CentreLine line = centre_line_of(x, m_centre_line);
  std::vector<std::pair<int, double>> w;
  Shape s;
  s.height = -parabolic_extreme(line.z, 1.0, w);
  s.width = parabolic_extreme(line.x, -1.0, w) - parabolic_extreme(line.x, 1.0, w);
  return s;
}

namespace {

// The loop's Newton settings. Exact Hessian with the Levenberg shift as the safeguard: the
// per-element projection (NewtonPolicy::project_psd) drops the θ∇²θ part of the bending
// Hessian, which is what turns the strip, and Newton then converges linearly (100+ iterations
// where the exact Hessian needs 5–30). The shell's preset with the projection is kept as a
// fallback (robust) for starts far from equilibrium.
struct LoopNewton {
  NewtonOptions exact, robust;
};

LoopNewton loop_newton(const PearLoopSetup& setup, const BendingParams& bending) {
  LoopNewton out;
  NewtonOptions& options = out.exact;
  options = NewtonOptions::for_shell_unprojected();
  options.max_iterations = 100;
  // The projected solve, which the exact one always follows, stops at the preset's tolerance.
  out.robust = NewtonOptions::for_shell();
  out.robust.max_iterations = 300;
  // Residual forces below 1e-8 of the loop's force scale are numerical noise: its weight
  // ρ g L W plus the force B W/L² that bends it to a radius of its length.
  const double L = setup.length, W = setup.width;
  const double k_max = std::max({bending.ktheta[0], bending.ktheta[1], bending.ktheta[2], 0.0});
  const double force_scale =
      setup.areal_density * setup.gravity * L * W + bending_stiffness_per_width(k_max) * W / (L * L);
  options.tolerance = 1e-8 * std::max(force_scale, 1e-300);
  return out;
}

// The slot of warm's state for clamp distance d (warm->clamp_distance.size() when it has
// none, 0 without a warm start): a state of n DOFs at a distance within 1e-12 · length of d.
std::size_t warm_slot(const PearLoopWarmStart* warm, double d, double length, int n) {
  std::size_t slot = warm ? warm->clamp_distance.size() : 0;
  if (warm) {
    for (std::size_t i = 0; i < warm->clamp_distance.size(); ++i)
      if (std::abs(warm->clamp_distance[i] - d) <= 1e-12 * length && warm->states[i].size() == n) slot = i;
  }
  return slot;
}

// Stores the equilibrium x at d in its slot (a new one past the end).
void keep_warm(PearLoopWarmStart& warm, std::size_t slot, double d, const Eigen::VectorXd& x) {
  if (slot < warm.clamp_distance.size()) {
    warm.states[slot] = x;
  } else {
    warm.clamp_distance.push_back(d);
    warm.states.push_back(x);
  }
}

// The equilibrium at sample.clamp_distance: from the warm state when there is one and it
// converges, else from the start loop x: exact Hessian, then the projected one, then exact
// again from where the projected solve stopped (it converges fast once near the equilibrium).
// x receives the last valid iterate; the sample its convergence, residual and failure, and the
// counts go to both. Returns whether it converged.
bool solve_loop(const TermList& terms, const std::vector<int>& fixed_dofs, const LoopNewton& newton,
                const Eigen::VectorXd* warm_state, Eigen::VectorXd& x, PearLoopSample& sample, PearLoopRun& out) {
  NewtonSummary summary;
  bool solved = false;
  const auto count = [&](const NewtonSummary& s) {
    ++out.newton_solves;
    out.newton_iterations += s.iterations;
    sample.newton_iterations += s.iterations;
  };
  if (warm_state) {
    Eigen::VectorXd trial = *warm_state;
    summary = solve_static(terms, trial, fixed_dofs, newton.exact);
    count(summary);
    if (summary.converged()) {
      x = trial;
      solved = true;
    }
  }
  const Eigen::VectorXd start_state = x;
  for (int attempt = 0; attempt < 3 && !solved; ++attempt) {
    Eigen::VectorXd trial = attempt == 1 ? start_state : x;
    summary = solve_static(terms, trial, fixed_dofs, attempt == 1 ? newton.robust : newton.exact);
    count(summary);
    if (summary.status != NewtonStatus::invalid_start) x = trial;
    solved = summary.converged();
  }
  sample.converged = solved;
  sample.residual = summary.residual;
  if (!solved)
    sample.message = "equilibrium at clamp distance " + std::to_string(sample.clamp_distance) +
                     " m failed: " + summary.brief();
  return solved;
}

// The loop's height, width, aspect ratio and largest curvature across the strip at x; a loop
// of no width is not converged.
void read_shape(const PearLoopScene::Shape& shape, const BendingTerm& bending, const std::vector<int>& across_edges,
                const Eigen::VectorXd& x, PearLoopSample& sample) {
  for (int e : across_edges) sample.max_curvature = std::max(sample.max_curvature, std::abs(bending.curvature(x, e)));
  sample.height = shape.height;
  sample.width = shape.width;
  sample.aspect_ratio = shape.width > 0.0 ? shape.height / shape.width : 0.0;
  if (!(std::isfinite(sample.aspect_ratio) && shape.width > 0.0)) {
    sample.converged = false;
    sample.aspect_ratio = 0.0;
    if (sample.message.empty()) sample.message = "degenerate loop (zero width)";
  }
}

struct LoopSensitivityInputs {
  const TermList& terms;
  const BendingTerm& bending;
  const std::vector<int>& free_index;  // free_dof_index of the scene
  int free_count;
  const std::vector<int>& centre_line;
};

// dr/dk_θ at the equilibrium x by the implicit function theorem: H_ff dx_f/dk = −∂g_f/∂k,
// carried through the parabolic read-outs of h and p. A stable equilibrium has a positive
// definite Hessian; otherwise the theorem gives no (meaningful) derivative.
void add_aspect_sensitivities(const LoopSensitivityInputs& in, const Eigen::VectorXd& x, PearLoopSample& sample) {
  const auto n = static_cast<int>(x.size());
  const int nf = in.free_count;
  const Eigen::SparseMatrix<double> H = total_hessian(in.terms, x, false);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(free_block(H, in.free_index, nf));
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
    sample.message = "sensitivities: the equilibrium Hessian is not positive definite";
    return;
  }
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, 3);
  in.bending.add_gradient_per_parameter(x, G);
  Eigen::MatrixXd rhs(nf, 3);
  for (int dof = 0; dof < n; ++dof)
    if (in.free_index[idx(dof)] >= 0) rhs.row(in.free_index[idx(dof)]) = -G.row(dof);
  const Eigen::MatrixXd dxf = ldlt.solve(rhs);  // dx_f/dk, nf × 3
  const auto dof_row = [&](int v, int axis) -> Eigen::RowVector3d {
    const int f = in.free_index[idx(BendingTerm::dim * v + axis)];
    return f >= 0 ? Eigen::RowVector3d(dxf.row(f)) : Eigen::RowVector3d::Zero();
  };
  const CentreLine line = centre_line_of(x, in.centre_line);
  std::vector<std::pair<int, double>> w;
  const auto dextreme = [&](const std::vector<double>& f, double sign, int axis) {
    parabolic_extreme(f, sign, w);
    Eigen::RowVector3d dv = Eigen::RowVector3d::Zero();
    for (const auto& [i, wi] : w) dv += wi * dof_row(in.centre_line[idx(i)], axis);
    return dv;
  };
  const Eigen::RowVector3d dh = -dextreme(line.z, 1.0, 2);
  const Eigen::RowVector3d dp = dextreme(line.x, -1.0, 0) - dextreme(line.x, 1.0, 0);
  const double h = sample.height, p = sample.width;
  sample.daspect_dktheta = ((p * dh - h * dp) / (p * p)).transpose();
  sample.has_sensitivities = sample.daspect_dktheta.allFinite();
  if (!sample.has_sensitivities) {
    sample.daspect_dktheta.setZero();
    sample.message = "sensitivities: not finite";
  }
}

}  // namespace

PearLoopRun PearLoopScene::run(const ShellParams& params, const std::vector<double>& clamp_distances,
                               bool with_sensitivities, PearLoopWarmStart* warm) const {
  const auto start = numerics::Clock::now();
  PearLoopRun out;
  const MembraneTerm membrane(m_mesh, params.inplane, BendingTerm::dim);
  const BendingTerm bending(m_mesh, params.bending);
  const GravityTerm gravity(m_mesh, m_setup.areal_density, m_setup.gravity);
  const TermList terms{&membrane, &bending, &gravity};
  out.effects = numerics::term_names(terms);
  const int n = BendingTerm::dim * m_mesh.vertex_count();
  const LoopNewton newton = loop_newton(m_setup, params.bending);
  // Free-DOF numbering for the sensitivities.
  int nf = 0;
  const std::vector<int> free_index = free_dof_index(n, m_fixed_dofs, nf);

  for (const double d : clamp_distances) {
    const auto t0 = numerics::Clock::now();
    PearLoopSample sample;
    sample.clamp_distance = d;
    Eigen::VectorXd x;
    try {
      x = initial_state(d);
    } catch (const Error& e) {
      sample.message = e.what();
      if (out.message.empty()) out.message = sample.message;
      out.samples.push_back(sample);
      continue;
    }
    // A warm state for this distance, if an earlier run left one.
    const std::size_t slot = warm_slot(warm, d, m_setup.length, n);
    const Eigen::VectorXd* warm_state = warm && slot < warm->clamp_distance.size() ? &warm->states[slot] : nullptr;
    const bool solved = solve_loop(terms, m_fixed_dofs, newton, warm_state, x, sample, out);
    read_shape(measure(x), bending, m_across_edges, x, sample);
    if (solved && warm) keep_warm(*warm, slot, d, x);
    if (sample.converged && with_sensitivities) {
      const LoopSensitivityInputs in{terms, bending, free_index, nf, m_centre_line};
      add_aspect_sensitivities(in, x, sample);
    }
    sample.seconds = numerics::seconds_since(t0);
    if (out.message.empty() && !sample.message.empty()) out.message = sample.message;
    out.samples.push_back(sample);
    if (!sample.converged && m_setup.stop_at_first_failure) break;
  }
  out.ok = true;
  for (const auto& s : out.samples)
    if (!s.converged || (with_sensitivities && !s.has_sensitivities)) out.ok = false;
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::shell
