#pragma once
// The FAB's loop-method bends (issue 51; docs/fab.md) as a 3-D scene: a strip of taut free
// length L × width W, both ends clamped flat and level (the stationary clamp on the load cell
// at x = −d/2, the moving one at x = +d/2, the strip leaving each clamp horizontally along the
// pull), the moving clamp brought closer (d < L), and the strip buckled into a loop upwards
// (U1) or downwards (D1, D2), sagging under its own weight (areal density ρ, z up). The
// width runs along y. Effects: membrane (3-D), bending, gravity.
//
// Read-out at each clamp distance d: the force along the pull on the stationary clamp,
// tension positive (what the load cell reads, zero removed): a buckled strip pushes, so it is
// negative. And the loop's height, the centre line's farthest point from the clamps' level.
//
// Mesh: one clamped cell at each end and the free cells between; every vertex of a clamped
// cell is fixed, which holds the tangent level as well as the position. A discrete clamp acts
// half a cell inside its cell, so the free mesh is one cell shorter than L (loop_bend.cpp).
// Cells default to L/25 along and a quarter of that across, so that the diagonals run nearly
// along the pull and stay flat.
//
// Start: the strip laid isometrically on the clamped–clamped buckling mode, tangent angle
// θ(s) = ±a sin(2π s/L) from the pull direction, whose span ∫ cos θ ds = L J₀(a) closes at d
// (a found from J₀(a) = d/L). Newton then finds the equilibrium.
//
// Known answer without gravity (tests/shell_fit/test_loop_bend.cpp): the inextensible
// elastica clamped at both ends buckles in four quarter waves, so with k = sin(α/2) the
// modulus of its largest angle α, L = 4K(k)/λ, d = L(2E(k)/K(k) − 1) and the push
// P = B W λ² = B W (4K(k)/L)², B = 2 k_θ per unit width (pear_loop.hpp); small loops tend to
// Euler's 4π² B W/L². Up and down loops then push alike.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "shell_fit/core/shell_mesh.hpp"
#include "shell_fit/core/shell_params.hpp"

namespace yarnfit::shell {

enum class LoopDirection { up, down };

struct LoopBendSetup {
  double length = 0.02;         // taut free length between the clamps, L [m]
  double width = 0.05;          // W [m]
  double material_angle = 0.0;  // weft axis from the strip's length [rad], as in the stretch scene
  double areal_density = 0.1;   // ρ [kg/m²]
  double gravity = 9.81;        // g [m/s²]
  LoopDirection direction = LoopDirection::down;
  int cells_along = 0;          // free cells along, even; 0 → 24
  int cells_across = 0;         // even; 0 → cells four times longer than wide
  int refinements = 0;          // midpoint subdivisions (mesh-convergence checks)
};

struct LoopBendSample {
  double clamp_distance = 0.0;  // d [m]
  double force = 0.0;           // along the pull on the stationary clamp, tension positive [N]
  double height = 0.0;          // the loop's farthest centre-line point from the clamps' level [m]
  double max_curvature = 0.0;   // the largest |κ| of any edge [1/m]: the range of the uniform targets
  bool converged = false;
  std::string message;
  int newton_iterations = 0;
  double residual = 0.0;
  double seconds = 0.0;
};

struct LoopBendRun {
  bool ok = false;
  std::string message;  // the first failure
  std::vector<LoopBendSample> samples;
  std::vector<std::string> effects;
  double seconds = 0.0;
};

class LoopBendScene {
 public:
  // Throws an input Error for non-positive or non-finite sizes, negative density or
  // gravity, or odd cell counts.
  explicit LoopBendScene(const LoopBendSetup& setup);

  // The loop at each clamp distance 0 < d < L, each from its own start, or from `warm`'s
  // state for that distance when one is given and Newton converges from it (a fit's next
  // evaluation at nearby parameters); `warm` then receives the new equilibria. Failures are
  // reported per sample, never thrown.
  [[nodiscard]] LoopBendRun run(const ShellParams& params, const std::vector<double>& clamp_distances,
                                std::vector<Eigen::VectorXd>* warm = nullptr) const;

  // The start state at d: the buckling mode laid isometrically; throws an input Error
  // unless 0 < d < L.
  [[nodiscard]] Eigen::VectorXd initial_state(double clamp_distance) const;

  [[nodiscard]] const ShellMesh& mesh() const { return m_mesh; }

 private:
  LoopBendSetup m_setup;
  ShellMesh m_mesh;
  double m_clamp = 0.0;  // clamped cell length c [m]
  std::vector<int> m_fixed_dofs;
  std::vector<int> m_stationary;   // vertices of the load cell's clamp
  std::vector<int> m_centre_line;  // vertices on y = 0
};

// The gravity-free clamped–clamped elastica's push P/(B W) [1/m²] at span d of a strip of
// length L (0 < d < L), by its elliptic integrals.
[[nodiscard]] double elastica_clamped_push(double span, double length);

}  // namespace yarnfit::shell
