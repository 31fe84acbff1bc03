#pragma once
// The clamped stretch test as a planar scene (SPEC §3, §4; thesis 6.2.3, 6.3.1).
//
// A rectangle of the swatch's free length × width, pull along +x, the material frame rotated
// by the test direction (weft 0, bias π/4, warp π/2). Both clamped edges are fully fixed; the
// right one is moved to x = length·(1 + u) (u: clamp stretch). Effects: membrane only — no
// out-of-plane DOFs, no bending, no gravity. Outputs at each measured stretch s:
//   force        total clamp reaction along the pull [N]
//   compression  c = 1 − w/w̄ at mid-length (free edges, or gauge marks ±width/2)
// where s is read where the test read it: between the clamps, or between gauge marks placed
// ±gauge_length/2 from the centre. With gauge marks the clamp stretch u that gives the
// measured s is found by a secant iteration, so outputs are compared at the same material
// stretch the rig recorded.
//
// Sensitivities (for the fit): at equilibrium g_f(x, p, u) = 0, so by the implicit function
// theorem dx_f/dp = −H_ff⁻¹ ∂g_f/∂p and dx_f/du = −H_fc ∂x_c/du mapped by H_ff⁻¹. Holding the
// measured stretch m fixed, du/dp = −(dm/dp)/(dm/du), and each output o gets
//   do/dp|_m = ∂o/∂p + (∂o/∂x)(dx/dp) + (do/du)(du/dp).
// One factorisation of H_ff serves all parameters.
//
// Warm starts (for a fit, which solves the same targets again and again with nearby
// parameters): a ClampedStretchWarmStart keeps each target's equilibrium, its clamp stretch
// and the slope dm/du of the measured stretch. A later run starts every target from there
// (with gauge marks, the first clamp correction uses the stored slope), so Newton needs a few
// iterations and the secant one or two solves; if that start fails, the target is solved from
// the previous target's state as without a warm start.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/solver/static_equilibrium.hpp"

namespace yarnfit::shell {

struct ClampedStretchSetup {
  double length = 0.10;         // free length between the clamps [m]
  double width = 0.06;          // [m]
  double material_angle = 0.0;  // weft axis angle from the pull [rad]
  std::optional<double> gauge_length;  // mark spacing along the pull [m]
  std::optional<double> gauge_width;   // mark spacing across, at mid-length [m]
  int nx = 0;            // cells along the pull (even); 0 → about 1 cell per `target_edge`
  int ny = 0;            // cells across (even)
  double target_edge = 5e-3;  // default cell size [m]
  int refinements = 0;   // midpoint subdivisions of the mesh (mesh-convergence checks)
  // Newton iterations one run may spend over all its targets before it gives up (0: no
  // limit). A fit sets it: a trial point that needs many times the usual effort is far from
  // any good fit, and failing fast lets the optimiser step back sooner.
  int max_newton_iterations = 0;
};

struct ClampedStretchSample {
  double measured_stretch = 0.0;  // s where the test reads it (gauge or clamps)
  double clamp_stretch = 0.0;     // u
  double force = 0.0;             // [N]
  double compression = 0.0;
  int newton_iterations = 0;      // spent on this target (warm start, secant, load steps)
  double residual = 0.0;          // largest force on a free node at the equilibrium [N]
  double seconds = 0.0;           // wall time of this target
  // d(force)/dp and d(compression)/dp at fixed measured stretch, p = k_inplane_param_names
  using ParameterVector = Eigen::Matrix<double, k_inplane_param_count, 1>;
  ParameterVector dforce_dp = ParameterVector::Zero();
  ParameterVector dcompression_dp = ParameterVector::Zero();
};

struct ClampedStretchRun {
  bool ok = false;
  std::string message;  // why it failed, when it did
  std::vector<ClampedStretchSample> samples;
  int newton_solves = 0;
  int newton_iterations = 0;
  double seconds = 0.0;
  std::vector<std::string> effects;  // the terms the scene assembled (its term list)
};

// Equilibria of earlier runs by target; filled and updated by ClampedStretchScene::run.
struct ClampedStretchWarmStart {
  std::vector<double> targets;        // measured stretch of each stored state
  std::vector<double> clamp_stretch;  // u of each
  std::vector<double> slope;          // dm/du there (0: unknown)
  std::vector<Eigen::VectorXd> states;
};

class ClampedStretchScene {
 public:
  explicit ClampedStretchScene(const ClampedStretchSetup& setup);

  // Simulates the test at the measured stretches `targets` (ascending, > −1) with `params`.
  [[nodiscard]] ClampedStretchRun run(const InplaneParams& params, const std::vector<double>& targets,
                                      bool with_sensitivities = false,
                                      ClampedStretchWarmStart* warm = nullptr) const;

  [[nodiscard]] const ShellMesh& mesh() const { return m_mesh; }
  [[nodiscard]] int vertex_count() const { return m_mesh.vertex_count(); }

 private:
  struct RunSolver;  // one run's equilibria along the clamp stretch (clamped_stretch.cpp)

  ClampedStretchSetup m_setup;
  ShellMesh m_mesh;
  std::vector<int> m_left, m_right;  // clamped vertices
  std::vector<int> m_fixed_dofs;
  std::vector<int> m_free_index;  // per DOF: its index among the free DOFs, −1 when clamped
  int m_free_count = 0;
  // Linear read-outs: measured length l = |Σ a_i x_i − Σ b_i x_i| etc. as weighted vertices.
  std::vector<std::pair<int, double>> m_len_a, m_len_b, m_wid_a, m_wid_b;
  double m_rest_len = 0.0, m_rest_wid = 0.0;
  bool m_stretch_from_clamps = true;
};

}  // namespace yarnfit::shell
