#include "shell_fit/scenes/loop_bend.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/energies/bending_term.hpp"
#include "shell_fit/energies/gravity_term.hpp"
#include "shell_fit/energies/membrane_term.hpp"
#include "shell_fit/mesh/rect_mesh.hpp"
#include "shell_fit/solver/static_equilibrium.hpp"
#include "numerics/util/index.hpp"

namespace yarnfit::shell {

namespace {

using std::numbers::pi;
constexpr int k_default_cells_along = 24;
constexpr double k_cell_aspect = 4.0;  // cell length along / width across

using numerics::idx;

// Bisection on a function that changes sign once on [lo, hi].
template <typename F>
double bisect(F f, double lo, double hi) {
  const bool rising = f(hi) > f(lo);
  for (int i = 0; i < 200 && hi - lo > 1e-15 * std::max(1.0, std::abs(hi)); ++i) {
    const double mid = 0.5 * (lo + hi);
    ((f(mid) > 0.0) == rising ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double elastica_clamped_push(double span, double length) {
  if (!(span > 0.0 && span < length)) throw Error(ErrorCategory::input, "elastica: the span must lie in (0, L)");
  const double ratio = span / length;
  // d/L = 2E(k)/K(k) − 1 falls from 1 (k = 0) towards −1 (k → 1).
  const double k = bisect([&](double m) { return 2.0 * std::comp_ellint_2(m) / std::comp_ellint_1(m) - 1.0 - ratio; },
                          0.0, 1.0 - 1e-12);
  const double lambda = 4.0 * std::comp_ellint_1(k) / length;
  return lambda * lambda;
}

LoopBendScene::LoopBendScene(const LoopBendSetup& setup) : m_setup(setup) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(setup.length) || !positive(setup.width))
    throw Error(ErrorCategory::input, "loop bend: length and width must be positive and finite");
  if (!std::isfinite(setup.areal_density) || setup.areal_density < 0.0 || !std::isfinite(setup.gravity) ||
      setup.gravity < 0.0)
    throw Error(ErrorCategory::input, "loop bend: areal density and gravity must be finite and ≥ 0");
  const int n = setup.cells_along == 0 ? k_default_cells_along : setup.cells_along;
  if (n < 4 || n % 2 != 0) throw Error(ErrorCategory::input, "loop bend: cells_along must be even and ≥ 4");
  int n_across = setup.cells_across;
  // Cells four times longer than wide: their diagonals then run nearly along the pull, across
  // the fold lines, and stay flat. With square cells the diagonals' hinges take a share of the
  // fold at a membrane cost that falls with the cell size, and the strip bends 10–20 % too
  // easily against the elastica (the pear loop's aspect ratio, which goes as B^(1/3), hides
  // most of that); at 4:1 it is within 1.5 % (tests/shell_fit/test_loop_bend.cpp).
  if (n_across == 0)
    n_across = std::max(2, 2 * static_cast<int>(std::lround(0.5 * k_cell_aspect * setup.width * (n + 1) / setup.length)));
  if (n_across < 2 || n_across % 2 != 0)
    throw Error(ErrorCategory::input, "loop bend: cells_across must be even and ≥ 2");
  if (setup.refinements < 0) throw Error(ErrorCategory::input, "loop bend: refinements must be ≥ 0");
  // The hinge on a clamp's edge spreads its fold over half of each neighbouring cell, so a
  // discrete clamp acts half a cell inside its clamped cell. The free mesh is therefore one
  // cell shorter than L and the clamped columns stand half a cell inwards: the strip then
  // bends over L between clamps at ±d/2, and the clamps' error falls from first to second
  // order in the cell size (tests/shell_fit/test_loop_bend.cpp).
  m_clamp = setup.length / (n + 1);
  m_mesh = make_rect_mesh(setup.length + m_clamp, setup.width, n + 2, n_across, setup.material_angle);
  for (int r = 0; r < setup.refinements; ++r) m_mesh = refine(m_mesh);
  const double tol = 1e-9 * setup.length;
  m_stationary = vertices_where(m_mesh, [&](const Eigen::Vector2d& p) { return p.x() <= m_clamp + tol; });
  const auto clamped = vertices_where(m_mesh, [&](const Eigen::Vector2d& p) {
    return p.x() <= m_clamp + tol || p.x() >= setup.length - tol;
  });
  m_fixed_dofs = vertex_dofs(clamped, BendingTerm::dim);
  m_centre_line = vertices_at_y(m_mesh, 0.0, tol);
}

Eigen::VectorXd LoopBendScene::initial_state(double clamp_distance) const {
  const double L = m_setup.length, d = clamp_distance;
  if (!(std::isfinite(d) && d > 0.0 && d < L))
    throw Error(ErrorCategory::input, "loop bend: the clamp distance must lie between 0 and the strip's length");
  // J₀ falls from 1 at a = 0 to 0 at its first root 2.405.
  const double a = bisect([&](double t) { return std::cyl_bessel_j(0.0, t) - d / L; }, 0.0, 2.404825557695773);
  const double sign = m_setup.direction == LoopDirection::up ? 1.0 : -1.0;
  constexpr int segments = 4000;
  const double ds = L / segments;
  std::vector<double> xs(idx(segments + 1), 0.0), zs(idx(segments + 1), 0.0);
  for (int i = 0; i < segments; ++i) {
    const double theta = sign * a * std::sin(2.0 * pi * (i + 0.5) / segments);
    xs[idx(i + 1)] = xs[idx(i)] + ds * std::cos(theta);
    zs[idx(i + 1)] = zs[idx(i)] + ds * std::sin(theta);
  }
  // The numerical span differs from d by the quadrature's error; scale x to close exactly.
  const double scale = d / xs.back();
  Eigen::VectorXd x(BendingTerm::dim * m_mesh.vertex_count());
  const double half = 0.5 * m_clamp;  // the clamps act half a cell inside their cells
  for (int v = 0; v < m_mesh.vertex_count(); ++v) {
    const double X = m_mesh.rest(v, 0), Y = m_mesh.rest(v, 1);
    const double s = X - m_clamp + half;  // arc length from where the stationary clamp acts
    double px = 0.0, pz = 0.0;
    if (s <= half) {
      px = -0.5 * d + s;
    } else if (s >= L - half) {
      px = 0.5 * d + (s - L);
    } else {
      const double u = std::clamp(s / ds, 0.0, static_cast<double>(segments));
      const int i = std::min(static_cast<int>(u), segments - 1);
      const double t = u - i;
      px = -0.5 * d + scale * ((1.0 - t) * xs[idx(i)] + t * xs[idx(i + 1)]);
      pz = (1.0 - t) * zs[idx(i)] + t * zs[idx(i + 1)];
    }
    x.segment<3>(BendingTerm::dim * v) << px, Y, pz;
  }
  return x;
}

LoopBendRun LoopBendScene::run(const ShellParams& params, const std::vector<double>& clamp_distances,
                               std::vector<Eigen::VectorXd>* warm) const {
  const auto start = numerics::Clock::now();
  LoopBendRun out;
  const MembraneTerm membrane(m_mesh, params.inplane, BendingTerm::dim);
  const BendingTerm bending(m_mesh, params.bending);
  const GravityTerm gravity(m_mesh, m_setup.areal_density, m_setup.gravity);
  const TermList terms{&membrane, &bending, &gravity};
  out.effects = numerics::term_names(terms);
  // Forces below 1e-8 of the strip's scale (its weight and the Euler push) are noise.
  const double k_max = std::max({params.bending.ktheta[0], params.bending.ktheta[1], params.bending.ktheta[2], 0.0});
  const double L = m_setup.length, W = m_setup.width;
  const double scale = m_setup.areal_density * m_setup.gravity * L * W + 2.0 * k_max * W * 4.0 * pi * pi / (L * L);
  // Exact Hessian first (the projected one loses the turning part of bending and crawls),
  // the projected preset as the fallback from the start, then exact again from there.
  NewtonOptions exact = NewtonOptions::for_shell_unprojected();
  exact.max_iterations = 100;
  exact.tolerance = 1e-8 * std::max(scale, 1e-300);
  NewtonOptions robust = NewtonOptions::for_shell();
  robust.max_iterations = 300;
  robust.tolerance = exact.tolerance;
  if (warm) warm->resize(clamp_distances.size());
  for (std::size_t i = 0; i < clamp_distances.size(); ++i) {
    const double d = clamp_distances[i];
    const auto t0 = numerics::Clock::now();
    LoopBendSample sample;
    sample.clamp_distance = d;
    Eigen::VectorXd x;
    try {
      x = initial_state(d);
    } catch (const Error& e) {
      sample.message = e.what();
    }
    NewtonSummary summary;
    if (warm && sample.message.empty() && (*warm)[i].size() == x.size()) {
      Eigen::VectorXd trial = (*warm)[i];
      summary = solve_static(terms, trial, m_fixed_dofs, exact);
      sample.newton_iterations += summary.iterations;
      if (summary.converged()) {
        x = trial;
        sample.converged = true;
      }
    }
    for (int attempt = 0; attempt < 3 && sample.message.empty() && !sample.converged; ++attempt) {
      Eigen::VectorXd trial = attempt == 1 ? initial_state(d) : x;
      summary = solve_static(terms, trial, m_fixed_dofs, attempt == 1 ? robust : exact);
      sample.newton_iterations += summary.iterations;
      if (summary.status != NewtonStatus::invalid_start) x = trial;
      sample.converged = summary.converged();
    }
    if (sample.message.empty()) {
      sample.residual = summary.residual;
      if (!sample.converged) sample.message = "loop at clamp distance " + std::to_string(d) + " m: " + summary.brief();
      // The clamp's reaction on the strip is +∂E/∂x; the strip's force on the load cell, along
      // the pull (+x from the stationary clamp), is its negative.
      sample.force = -clamp_force(terms, x, m_stationary, BendingTerm::dim, 0);
      // A failed point seeds nothing: its state is of no equilibrium, nor of this k_θ's.
      if (warm) (*warm)[i] = sample.converged ? x : Eigen::VectorXd();
      for (const int v : m_centre_line)
        if (std::abs(x[BendingTerm::dim * v + 2]) > std::abs(sample.height)) sample.height = x[BendingTerm::dim * v + 2];
      if (sample.converged)
        for (int e = 0; e < static_cast<int>(bending.edges().size()); ++e)
          sample.max_curvature = std::max(sample.max_curvature, std::abs(bending.curvature(x, e)));
    }
    sample.seconds = numerics::seconds_since(t0);
    if (out.message.empty() && !sample.converged) out.message = sample.message;
    out.samples.push_back(sample);
  }
  out.ok = std::all_of(out.samples.begin(), out.samples.end(), [](const LoopBendSample& s) { return s.converged; });
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::shell
