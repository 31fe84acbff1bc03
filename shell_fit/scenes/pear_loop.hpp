#pragma once
// The pear-loop bending test (Peirce 1930) as a 3-D scene (SPEC §3, §4; thesis 6.2.3, 6.3.2).
//
// A strip of the swatch's free length L × width W is bent into a loop: both ends are clamped
// vertically (the strip leaves each clamp pointing straight down, −z), the clamps at the same
// height z = 0 and a horizontal distance d apart along x, and the loop hangs below them under
// gravity (areal density ρ, z up). The width runs along y, out of the loop's plane.
// Effects: membrane (3-D), bending, gravity.
//
// Mesh: the rest rectangle is the free length plus one clamped cell at each end,
// [0, L + 2c] × [−W/2, W/2] with c the coarse cell length. Every vertex in a clamped cell is
// fixed (at least two vertex columns per end, so the clamp holds the tangent vertical as well
// as the position): the left clamp holds rest X ∈ [0, c] at x = −d/2, z = c − X, the right one
// X ∈ [L + c, L + 2c] at x = +d/2, z = X − L − c. The free strip starts and ends at z = 0.
// Refinement subdivides the clamped cells too, so the clamp stays the same physical region.
//
// Output at each clamp distance d, measured on the centre line y = 0 of the strip (the
// deformation is nearly cylindrical: the depth of the other lines along the strip differs by
// well under 1 %):
//   h = −min z          depth of the loop's lowest point below the clamps [m]
//   p = max x − min x   the loop's widest horizontal width [m]
//   r = h/p             aspect ratio
// Each extreme is the vertex of the parabola through the extreme vertex and its two
// neighbours along the line (vertices are evenly spaced in rest arc length), which makes r a
// smooth function of the parameters (a plain vertex maximum jumps when the extreme moves from
// one vertex to the next) and removes most of the sampling error; at the ends of the line, or
// without a strict local extreme, the vertex value itself.
//
// Start: the strip laid isometrically on a smooth symmetric loop of arc length L with
// vertical ends at x = ±d/2: tangent angle (from +x, in the x–z plane) along the left half
//   θ(s) = −π/2 + (π/2)(s/S) − a sin(π s/S),   S = L/2,
// from straight down at the clamp to horizontal at the bottom; a > 0 bulges the loop outwards
// first (the pear), and a is found by the root finder (numerics/roots) so that the half loop closes at x = 0:
// ∫₀^S cos θ ds = d/2. The right half mirrors the left. Newton then finds the equilibrium.
//
// Sensitivities (for the fit): at equilibrium g_f(x, k) = 0, so dx_f/dk = −H_ff⁻¹ ∂g_f/∂k
// (BendingTerm::add_gradient_per_parameter, one factorisation for the 3 parameters), and
//   dr/dk = (p dh/dk − h dp/dk)/p²,  dh/dk, dp/dk through the parabolic extremes.
//
// Bending stiffness per unit width implied by the model: BendingTerm's edge energy reproduces
// Ψ = k_θ κ² exactly for a cylinder bent about an axis along an edge family of our rectangle
// meshes (the loop's state), so the moment per unit width is ∂Ψ/∂κ = 2 k_θ κ and
//   B = 2 k_θ  [N·m = N·m²/m],   bending length ℓ = (B/(ρ g))^(1/3)
// (k_θ of the edges across the strip: effective_ktheta). tests/shell_fit/test_pear_loop.cpp
// checks B on the scene's mesh. For a nearly inextensible strip, r depends on d, L and the
// stiffnesses only through d/ℓ and L/ℓ: the loop's shape is fixed by bending against gravity.
//
// Accuracy (L = 10 cm, ℓ = 1–3 cm, d = 3–34 mm, default square cells of 2.5 mm): within 1 % of
// the twice-subdivided mesh, and within 3 % of the inextensible planar elastica (shooting
// solution of B θ'' = ρ g (S − s) cos θ − λ sin θ); the remaining difference is the shell's
// own: the membrane's stiffness moves r by up to ±2 % at d = 3 mm through slightly
// non-cylindrical shapes (an elastica has no width).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"
#include "shell_fit/solver/static_equilibrium.hpp"

namespace yarnfit::shell {

struct PearLoopSetup {
  double length = 0.10;         // free length of the strip between the clamps, L [m]
  double width = 0.06;          // W [m]
  // Weft axis angle from the strip's length [rad]: −pull_angle, as in the clamped stretch
  // (0 weft, −π/4 bias, −π/2 warp).
  double material_angle = 0.0;
  double areal_density = 0.2;   // ρ [kg/m²]
  double gravity = 9.81;        // g [m/s²]
  // Cells along the free length (even); 0 → about length/target_edge. The clamped cells
  // come on top (one per end).
  int cells_along = 0;
  // Cells across (even); 0 → cells about as wide as they are long. Keep them near square:
  // with long thin cells the hinges of the diagonals, nearly parallel to the fold lines,
  // share the loop's folding with them at almost no membrane strain, and since the hinge
  // energy is quadratic in each angle, two hinges with half the angle cost half as much. The
  // loop then bends as if k_θ were much smaller (docs/shell-fit.md); with square cells the
  // diagonals lie at 45° and folding them stretches the membrane, and r converges to the
  // inextensible elastica's.
  int cells_across = 0;
  double target_edge = 2.5e-3;  // default cell size [m]
  int refinements = 0;          // midpoint subdivisions (mesh-convergence checks)
  // End a run at its first distance without an equilibrium (the rest are not simulated): a
  // check of a law against a record needs no more than that one failure to say so.
  bool stop_at_first_failure = false;
};

struct PearLoopSample {
  double clamp_distance = 0.0;  // d [m]
  double aspect_ratio = 0.0;    // r = h/p
  double height = 0.0;          // h [m]
  double width = 0.0;           // p [m]
  bool converged = false;       // false: h, p, r belong to the last valid Newton iterate
  std::string message;          // why the equilibrium failed, when it did
  int newton_iterations = 0;
  double residual = 0.0;        // largest force on a free node at the returned state [N]
  double seconds = 0.0;
  // Largest |κ| = |θ|/H over the edges across the strip (the loop's curvature, including the
  // kink where the strip leaves a clamp) [1/m]: the curvature range the uniform bending
  // targets should cover.
  double max_curvature = 0.0;
  // dr/dk_θ (weft, bias, warp) [1/(N·m)] at fixed d; valid when has_sensitivities.
  bool has_sensitivities = false;
  Eigen::Vector3d daspect_dktheta = Eigen::Vector3d::Zero();
};

struct PearLoopRun {
  bool ok = false;       // every distance converged (and, if asked, has sensitivities)
  std::string message;   // the first failure
  std::vector<PearLoopSample> samples;  // one per clamp distance, in the order given
  int newton_solves = 0;
  int newton_iterations = 0;
  double seconds = 0.0;
  std::vector<std::string> effects;  // the terms the scene assembled (its term list)
};

// Equilibria of earlier runs, reused as starting states when the same distances are solved
// again with nearby parameters (a fit): Newton then needs a few iterations instead of
// bending the strip from the start shape. Filled and updated by PearLoopScene::run.
struct PearLoopWarmStart {
  std::vector<double> clamp_distance;
  std::vector<Eigen::VectorXd> states;
};

class PearLoopScene {
 public:
  // Throws an input Error for non-positive or non-finite sizes, density or gravity,
  // or odd/too small cell counts.
  explicit PearLoopScene(const PearLoopSetup& setup);

  // Simulates the loop at each clamp distance d [m] (0 ≤ d, and small enough for a loop of
  // length L: up to about 0.6 L). Numerical failures are reported per sample, never thrown.
  [[nodiscard]] PearLoopRun run(const ShellParams& params, const std::vector<double>& clamp_distances,
                                bool with_sensitivities = false, PearLoopWarmStart* warm = nullptr) const;

  // The start state at clamp distance d (flat, 3 per vertex); throws an input Error
  // when no loop of length L closes at that distance.
  [[nodiscard]] Eigen::VectorXd initial_state(double clamp_distance) const;

  struct Shape {
    double height = 0.0;  // h [m]
    double width = 0.0;   // p [m]
    [[nodiscard]] double aspect_ratio() const { return height / width; }
  };
  [[nodiscard]] Shape measure(const Eigen::VectorXd& x) const;

  // Share of the bent edges' stiffness that comes from k_θ weft, bias, warp (sums to 1): the
  // edges across the strip carry the loop's curvature, and their rest direction in the
  // material frame decides which of the three k_θ the test measures. This keeps the fit
  // independent of BendingTerm's angle convention.
  [[nodiscard]] const Eigen::Vector3d& governing_weights() const { return m_governing; }
  // Index (0 weft, 1 bias, 2 warp) of the k_θ that dominates governing_weights().
  [[nodiscard]] int governing_ktheta() const;
  // k_θ of the bent edges for these parameters, Σ_j w_j k_j [N·m].
  [[nodiscard]] double effective_ktheta(const BendingParams& p) const;

  [[nodiscard]] const ShellMesh& mesh() const { return m_mesh; }
  [[nodiscard]] const PearLoopSetup& setup() const { return m_setup; }
  [[nodiscard]] const std::vector<int>& fixed_dofs() const { return m_fixed_dofs; }

 private:
  PearLoopSetup m_setup;
  ShellMesh m_mesh;
  double m_clamp = 0.0;            // clamped cell length c [m]
  std::vector<int> m_fixed_dofs;
  std::vector<int> m_centre_line;  // vertices on y = 0, by rest x
  std::vector<int> m_across_edges; // BendingTerm edge indices of the edges across the strip
  Eigen::Vector3d m_governing = Eigen::Vector3d::Zero();
};

// B = 2 k_θ: bending stiffness per unit width [N·m] of the model (derivation above).
[[nodiscard]] double bending_stiffness_per_width(double ktheta_effective);
// ℓ = (B/(ρ g))^(1/3) [m].
[[nodiscard]] double bending_length(double ktheta_effective, double areal_density, double g = 9.81);
// The inverse: k_θ whose bending length is ℓ.
[[nodiscard]] double ktheta_for_bending_length(double length, double areal_density, double g = 9.81);

}  // namespace yarnfit::shell
