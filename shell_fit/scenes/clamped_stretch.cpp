#include "shell_fit/scenes/clamped_stretch.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "numerics/roots/bracketed_root.hpp"
#include "numerics/util/clock.hpp"
#include "numerics/util/error.hpp"
#include "shell_fit/energies/membrane_term.hpp"
#include "shell_fit/mesh/rect_mesh.hpp"

namespace yarnfit::shell {

namespace {

constexpr int k_plane_dim = 2;

using Weights = std::vector<std::pair<int, double>>;

// Vertex weights of a rest material point (barycentric in its triangle).
Weights point_weights(const ShellMesh& mesh, const Eigen::Vector2d& rest_point) {
  const MaterialPoint mp = locate(mesh, rest_point);
  Weights w;
  for (int k = 0; k < 3; ++k) w.emplace_back(mesh.triangles(mp.triangle, k), mp.weights(k));
  return w;
}

Eigen::Vector2d position(const Weights& w, const Eigen::VectorXd& x) {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (const auto& [v, a] : w) p += a * x.segment<2>(k_plane_dim * v);
  return p;
}

// Distance between two weighted points and its gradient with respect to x.
double distance(const Weights& a, const Weights& b, const Eigen::VectorXd& x, Eigen::VectorXd* grad) {
  const Eigen::Vector2d d = position(b, x) - position(a, x);
  const double len = d.norm();
  if (grad) {
    grad->setZero(x.size());
    const Eigen::Vector2d n = d / len;
    for (const auto& [v, w] : b) grad->segment<2>(k_plane_dim * v) += w * n;
    for (const auto& [v, w] : a) grad->segment<2>(k_plane_dim * v) -= w * n;
  }
  return len;
}

int nearest_vertex(const ShellMesh& mesh, const Eigen::Vector2d& p) {
  int best = 0;
  double best_d = 1e300;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const double d = (mesh.rest.row(v).transpose() - p).norm();
    if (d < best_d) {
      best_d = d;
      best = v;
    }
  }
  return best;
}

}  // namespace

ClampedStretchScene::ClampedStretchScene(const ClampedStretchSetup& setup) : m_setup(setup) {
  if (!(setup.length > 0.0 && setup.width > 0.0))
    throw Error(ErrorCategory::input, "clamped stretch: length and width must be positive");
  int nx = setup.nx, ny = setup.ny;
  if (nx == 0 || ny == 0) std::tie(nx, ny) = default_resolution(setup.length, setup.width, setup.target_edge);
  m_mesh = make_rect_mesh(setup.length, setup.width, nx, ny, setup.material_angle);
  for (int r = 0; r < setup.refinements; ++r) m_mesh = refine(m_mesh);

  const double tol = 1e-9 * setup.length;
  m_left = vertices_at_x(m_mesh, 0.0, tol);
  m_right = vertices_at_x(m_mesh, setup.length, tol);
  for (int v : m_left) m_fixed_dofs.insert(m_fixed_dofs.end(), {k_plane_dim * v, k_plane_dim * v + 1});
  for (int v : m_right) m_fixed_dofs.insert(m_fixed_dofs.end(), {k_plane_dim * v, k_plane_dim * v + 1});
  // The free/clamped split depends only on the mesh; the sensitivities reuse it at every target.
  m_free_index = free_dof_index(k_plane_dim * m_mesh.vertex_count(), m_fixed_dofs, m_free_count);

  const double mid = 0.5 * setup.length;
  if (setup.gauge_length) {
    if (!(*setup.gauge_length > 0.0 && *setup.gauge_length < setup.length))
      throw Error(ErrorCategory::input, "clamped stretch: gauge length must lie between the clamps");
    m_len_a = point_weights(m_mesh, {mid - 0.5 * *setup.gauge_length, 0.0});
    m_len_b = point_weights(m_mesh, {mid + 0.5 * *setup.gauge_length, 0.0});
    m_rest_len = *setup.gauge_length;
    m_stretch_from_clamps = false;
  } else {
    m_rest_len = setup.length;
  }
  if (setup.gauge_width) {
    if (!(*setup.gauge_width > 0.0 && *setup.gauge_width <= setup.width))
      throw Error(ErrorCategory::input, "clamped stretch: gauge width must lie on the fabric");
    m_wid_a = point_weights(m_mesh, {mid, -0.5 * *setup.gauge_width});
    m_wid_b = point_weights(m_mesh, {mid, 0.5 * *setup.gauge_width});
    m_rest_wid = *setup.gauge_width;
  } else {
    // The free edges at mid-length are mesh vertices (nx and ny are even).
    m_wid_a = {{nearest_vertex(m_mesh, {mid, -0.5 * setup.width}), 1.0}};
    m_wid_b = {{nearest_vertex(m_mesh, {mid, 0.5 * setup.width}), 1.0}};
    m_rest_wid = setup.width;
  }
}

namespace {

// Newton settings of one load step. A healthy load step converges in a handful of iterations
// from the affine prediction; one that needs dozens is in trouble (a fit's trial point near
// inversion) and should fail fast so the optimiser can step back, instead of grinding.
NewtonOptions load_step_options(const InplaneParams& params, double width) {
  NewtonOptions options = NewtonOptions::for_shell();
  options.max_iterations = 40;
  // Residual forces below 1e-9 of the force a unit strain would need are numerical noise.
  const double force_scale = std::max({params.kxx, params.kyy, params.kxy, params.kss, 1e-12}) * width;
  options.tolerance = 1e-9 * force_scale;
  return options;
}

// Sizes the warm start for `count` targets, emptying it when it was kept for another count.
void size_warm_start(ClampedStretchWarmStart& warm, std::size_t count) {
  if (warm.targets.size() == count) return;
  warm.targets.assign(count, std::nan(""));
  warm.clamp_stretch.assign(count, 0.0);
  warm.slope.assign(count, 0.0);
  warm.states.assign(count, Eigen::VectorXd());
}

}  // namespace

// One run's equilibria: the state x at clamp stretch u_prev (the last equilibrium), moved
// along the clamp stretch by solves warm-started from it; the counts and the failure go to
// `out`.
struct ClampedStretchScene::RunSolver {
  RunSolver(const ClampedStretchScene& of, const MembraneTerm& term, ClampedStretchRun& run,
            const NewtonOptions& load_step)
      : scene(of), membrane(term), terms{&term}, out(run), options(load_step), n(k_plane_dim * of.m_mesh.vertex_count()),
        x(n) {
    for (int v = 0; v < scene.m_mesh.vertex_count(); ++v)
      x.segment<2>(k_plane_dim * v) = scene.m_mesh.rest.row(v).transpose();
    rest = x;
  }

  const ClampedStretchScene& scene;
  const MembraneTerm& membrane;
  const TermList terms;
  ClampedStretchRun& out;
  const NewtonOptions options;
  const int n;
  Eigen::VectorXd x, rest;
  double u_prev = 0.0;

  // Places the right clamp at stretch u, predicting the interior by stretching the last
  // solution's x-coordinates affinely.
  void set_clamp(double u, Eigen::VectorXd& state) const {
    const double scale = (1.0 + u) / (1.0 + u_prev);
    for (int v = 0; v < scene.m_mesh.vertex_count(); ++v) state[k_plane_dim * v] *= scale;
    for (int v : scene.m_left) state.segment<2>(k_plane_dim * v) = rest.segment<2>(k_plane_dim * v);
    for (int v : scene.m_right) {
      state[k_plane_dim * v] = scene.m_setup.length * (1.0 + u);
      state[k_plane_dim * v + 1] = rest[k_plane_dim * v + 1];
    }
  }

  // The equilibrium at clamp stretch u from the affine prediction, or failing that by load
  // steps from the last one; false (out.message says why) when it fails or the Newton budget
  // is spent.
  bool solve_at(double u) {
    Eigen::VectorXd trial = x;
    set_clamp(u, trial);
    NewtonSummary s;
    if (std::isfinite(total_energy(terms, trial))) s = solve_static(terms, trial, scene.m_fixed_dofs, options);
    if (!s.converged()) {
      out.newton_iterations += s.iterations;
      // Walk there from the last good state in load steps.
      trial = x;
      const double u0 = u_prev;
      ContinuationOptions copt;
      copt.newton = options;
      copt.newton.max_iterations = 25;
      copt.min_step = 1.0 / 64.0;
      s = solve_continuation(terms, trial, scene.m_fixed_dofs,
                             [&](double lambda, Eigen::VectorXd& state) {
                               const double target = u0 + lambda * (u - u0);
                               for (int v : scene.m_right) state[k_plane_dim * v] = scene.m_setup.length * (1.0 + target);
                             },
                             copt);
    }
    ++out.newton_solves;
    out.newton_iterations += s.iterations;
    if (!s.converged()) {
      out.message = "equilibrium at clamp stretch " + std::to_string(u) + " failed: " + s.brief();
      return false;
    }
    if (scene.m_setup.max_newton_iterations > 0 && out.newton_iterations > scene.m_setup.max_newton_iterations) {
      out.message = "Newton iteration budget of " + std::to_string(scene.m_setup.max_newton_iterations) + " spent";
      return false;
    }
    x = trial;
    u_prev = u;
    return true;
  }

  // The warm state of an earlier run at clamp stretch u, if it converges within `budget`.
  bool solve_from(const Eigen::VectorXd& state, double u, const NewtonOptions& budget) {
    Eigen::VectorXd trial = state;
    NewtonSummary s;
    if (std::isfinite(total_energy(terms, trial))) s = solve_static(terms, trial, scene.m_fixed_dofs, budget);
    ++out.newton_solves;
    out.newton_iterations += s.iterations;
    if (!s.converged()) return false;
    x = trial;
    u_prev = u;
    return true;
  }

  // The measured stretch of `state` (gauge marks, or the clamps), and its gradient.
  double measured(const Eigen::VectorXd& state, Eigen::VectorXd* grad) const {
    if (scene.m_stretch_from_clamps) {
      if (grad) grad->setZero(n);
      return state[k_plane_dim * scene.m_right[0]] / scene.m_setup.length - 1.0;
    }
    return distance(scene.m_len_a, scene.m_len_b, state, grad) / scene.m_rest_len - 1.0;
  }

  // Clamp stretch u with measured(u) = target: exact without gauge marks; with them the
  // gauge stretch grows with the clamp stretch, and the root finder (numerics/roots) solves
  // measured(u) = target from the warm start's u, each evaluation an equilibrium warm-started
  // from the last. Its first step uses the slope the warm start remembers, and `slope`
  // receives the secant of its last two solves. `solved`: x is already the equilibrium at u.
  bool reach(double target, bool solved, double& u, double& slope) {
    if (scene.m_stretch_from_clamps) {
      if (!solved) {
        u = target;
        if (!solve_at(u)) return false;
      }
      slope = 1.0;
      return true;
    }
    if (!solved) u = u_prev + (target - measured(x, nullptr));
    double u_last = std::nan(""), m_last = std::nan(""), u_before = std::nan(""), m_before = std::nan("");
    numerics::RootFindOptions ro;
    ro.lower = -0.5;  // the clamps never pass half the free length's compression
    ro.upper = 10.0;
    ro.initial_step = 1e-3 * (1.0 + std::abs(u));
    ro.initial_slope = slope > 0.0 ? slope : 0.0;
    ro.x_tolerance = 1e-13;
    ro.f_tolerance = 1e-10 * (1.0 + std::abs(target));
    ro.max_evaluations = 31;
    const numerics::RootResult root = numerics::find_root(
        [&](double uu) -> std::optional<double> {
          // The state is already the equilibrium at u_prev (a warm or earlier solve).
          if (!(solved && uu == u_prev) && !solve_at(uu)) return std::nullopt;
          solved = true;
          u_before = u_last;
          m_before = m_last;
          u_last = uu;
          m_last = measured(x, nullptr);
          return m_last - target;
        },
        u, ro);
    if (root.status == numerics::RootStatus::evaluation_failed) return false;  // solve_at said why
    // The secant of the last two solves: the next run's first step.
    if (std::isfinite(u_before) && std::abs(u_last - u_before) > 1e-7 * (1.0 + std::abs(u_last))) {
      const double secant = (m_last - m_before) / (u_last - u_before);
      if (secant > 0.0) slope = secant;
    }
    u = u_prev;
    if (!(std::abs(measured(x, nullptr) - target) <= 1e-6 * (1.0 + std::abs(target)))) {
      out.message = "gauge stretch " + std::to_string(target) + " not reached (clamp stretch " + std::to_string(u) +
                    ", " + numerics::to_string(root.status) + " after " + std::to_string(root.evaluations) +
                    " solves)";
      return false;
    }
    return true;
  }

  // Force, measured stretch, compression and residual of the equilibrium x at clamp stretch u;
  // `dwidth` receives the gradient of the measured width.
  ClampedStretchSample sample_at(double u, Eigen::VectorXd& dwidth) const {
    ClampedStretchSample sample;
    sample.clamp_stretch = u;
    sample.measured_stretch = measured(x, nullptr);
    const Eigen::VectorXd g = total_gradient(terms, x);
    for (int v : scene.m_right) sample.force += g[k_plane_dim * v];
    for (int d = 0; d < n; ++d)
      if (scene.m_free_index[static_cast<std::size_t>(d)] >= 0)
        sample.residual = std::max(sample.residual, std::abs(g[d]));
    dwidth.resize(n);
    const double w = distance(scene.m_wid_a, scene.m_wid_b, x, &dwidth);
    sample.compression = 1.0 - w / scene.m_rest_wid;
    return sample;
  }

  static constexpr int np = k_inplane_param_count;

  // The equilibrium's derivatives by the implicit function theorem: the true (unprojected)
  // Hessian H, ∂g/∂p (G, n × np) and the full-length dx/dp_k and dx/du (dx, n × (np + 1);
  // fixed DOFs: 0 for p, ∂x_c/∂u for u).
  struct Derivatives {
    Eigen::SparseMatrix<double> H;
    Eigen::MatrixXd G, dx;
  };

  std::optional<Derivatives> derivatives() const {
    const std::vector<int>& free_index = scene.m_free_index;
    const int nf = scene.m_free_count;
    Derivatives out_d;
    const Eigen::SparseMatrix<double>& H = out_d.H = total_hessian(terms, x, false);
    Eigen::VectorXd hfc_du = Eigen::VectorXd::Zero(nf);  // H_fc · ∂x_c/∂u
    Eigen::VectorXd dxc_du = Eigen::VectorXd::Zero(n);
    for (int v : scene.m_right) dxc_du[k_plane_dim * v] = scene.m_setup.length;
    Eigen::VectorXd hxc_du = H * dxc_du;  // full-length product, rows split below
    for (int d = 0; d < n; ++d)
      if (free_index[static_cast<std::size_t>(d)] >= 0) hfc_du[free_index[static_cast<std::size_t>(d)]] = hxc_du[d];
    const Eigen::SparseMatrix<double> Hff = free_block(H, free_index, nf);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Hff);
    if (ldlt.info() != Eigen::Success) return std::nullopt;
    Eigen::MatrixXd& G = out_d.G = Eigen::MatrixXd::Zero(n, np);
    membrane.add_gradient_per_parameter(x, G);
    Eigen::MatrixXd rhs(nf, np + 1);
    for (int d = 0; d < n; ++d) {
      const int f = free_index[static_cast<std::size_t>(d)];
      if (f < 0) continue;
      rhs.block<1, np>(f, 0) = -G.row(d);
    }
    rhs.col(np) = -hfc_du;
    const Eigen::MatrixXd sol = ldlt.solve(rhs);  // columns: dx_f/dp_k (k < np), dx_f/du
    Eigen::MatrixXd& dx = out_d.dx;
    dx.resize(n, np + 1);
    dx.setZero();
    for (int d = 0; d < n; ++d) {
      const int f = free_index[static_cast<std::size_t>(d)];
      if (f >= 0) dx.row(d) = sol.row(f);
    }
    dx.col(np) += dxc_du;
    return out_d;
  }

  // d(force)/dp and d(compression)/dp at fixed measured stretch; `slope` receives dm/du.
  void add_sensitivities(const Derivatives& dv, const Eigen::VectorXd& dwidth, ClampedStretchSample& sample,
                         double& slope) const {
    // Force = Σ_right g_x: dF = ∂g/∂p + H dx (rows of the right clamp's x DOFs).
    const Eigen::MatrixXd Hdx = dv.H * dv.dx;
    Eigen::Matrix<double, np + 1, 1> dF = Eigen::Matrix<double, np + 1, 1>::Zero();
    for (int v : scene.m_right) {
      dF += Hdx.row(k_plane_dim * v).transpose();
      dF.head<np>() += dv.G.row(k_plane_dim * v).transpose();
    }
    Eigen::VectorXd dmeasured(n);
    measured(x, &dmeasured);
    const Eigen::Matrix<double, np + 1, 1> dm = dv.dx.transpose() * dmeasured;
    const Eigen::Matrix<double, np + 1, 1> dc = -(dv.dx.transpose() * dwidth) / scene.m_rest_wid;
    // Hold the measured stretch: u moves with p unless the stretch is read at the clamps.
    ClampedStretchSample::ParameterVector du_dp = ClampedStretchSample::ParameterVector::Zero();
    if (!scene.m_stretch_from_clamps) du_dp = -dm.head<np>() / dm[np];
    sample.dforce_dp = dF.head<np>() + dF[np] * du_dp;
    sample.dcompression_dp = dc.head<np>() + dc[np] * du_dp;
    if (dm[np] > 0.0) slope = dm[np];
  }
};

ClampedStretchRun ClampedStretchScene::run(const InplaneParams& params, const std::vector<double>& targets,
                                           bool with_sensitivities, ClampedStretchWarmStart* warm) const {
  const auto start = numerics::Clock::now();
  ClampedStretchRun out;
  const MembraneTerm membrane(m_mesh, params, k_plane_dim);
  RunSolver solver(*this, membrane, out, load_step_options(params, m_setup.width));
  out.effects = numerics::term_names(solver.terms);
  // A warm state's solve that needs more than this is not worth finishing: the target is then
  // solved from the previous target's state instead.
  NewtonOptions warm_options = solver.options;
  warm_options.max_iterations = 20;
  if (warm) size_warm_start(*warm, targets.size());

  for (std::size_t i = 0; i < targets.size(); ++i) {
    const double target = targets[i];
    const auto target_start = numerics::Clock::now();
    const int iterations_before = out.newton_iterations;
    if (!(target > -1.0)) {
      out.message = "stretch target " + std::to_string(target) + " is not > -1";
      return out;
    }
    const bool have_warm = warm && std::abs(warm->targets[i] - target) <= 1e-12 * (1.0 + std::abs(target)) &&
                           warm->states[i].size() == solver.n;
    double slope = have_warm ? warm->slope[i] : 0.0;  // dm/du, 0 while unknown
    double u = 0.0;
    const bool solved = have_warm && solver.solve_from(warm->states[i], warm->clamp_stretch[i], warm_options);
    if (solved) u = warm->clamp_stretch[i];
    if (!solver.reach(target, solved, u, slope)) return out;

    Eigen::VectorXd dwidth;
    ClampedStretchSample sample = solver.sample_at(u, dwidth);
    sample.newton_iterations = out.newton_iterations - iterations_before;
    if (with_sensitivities) {
      const std::optional<RunSolver::Derivatives> dv = solver.derivatives();
      if (!dv) {
        out.message = "sensitivities: the equilibrium Hessian could not be factorised";
        return out;
      }
      solver.add_sensitivities(*dv, dwidth, sample, slope);
    }
    sample.seconds = numerics::seconds_since(target_start);
    out.samples.push_back(sample);
    if (warm) {
      warm->targets[i] = target;
      warm->clamp_stretch[i] = u;
      warm->slope[i] = slope;
      warm->states[i] = solver.x;
    }
  }
  out.ok = true;
  out.seconds = numerics::seconds_since(start);
  return out;
}

}  // namespace yarnfit::shell
