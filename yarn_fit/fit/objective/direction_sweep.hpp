#pragma once
// One direction's share of the yarn objective (thesis 6.5.3, eq. 6.11; yarn_objective.hpp): the
// tile, from its rest state, pulled through the direction's stretch samples, each at its
// zero-orthogonal-stress compression c*, and the samples compared with the targets.
//
//  * Stretches s_i: `samples` points evenly over the targets' range [s_first, s_last].
//  * c* at every sample (default), by continuation along s: each search starts from the
//    previous sample's equilibrium, at its c* moved by the targets' change of c; or, as in the
//    thesis, at `compression_nodes` samples only (2: both ends) and linear in between, the
//    other samples solved at that c, each warm-started from a march at the targets' shape.
//  * Every search accepts the first c whose orthogonal stress |∂Ψ/∂c| is within a band of the
//    direction's stress norm; with `root_correction` the band is found to first order from that
//    solve (yarn_fit/homogenise/sensitivity.hpp: root c* = c − f/f_c, half-width τ/f_c) and the
//    sample's c is the band's point nearest the targets' c, σ_s moved with it, so that the
//    read-outs are smooth in θ and no longer depend on where the search entered the band.
//    Samples whose band is wider than ±flat_band (Ψ nearly flat in c) are counted, and so are
//    those where d²Ψ/dc² ≤ 0 (c held where accepted).
//  * With parameters to differentiate by (`wanted`), every sample also carries dS/dθ and dc/dθ
//    at the held rest state: at a free c*, dc*/dθ = −(d∂Ψ/∂c/dθ) / (d²Ψ/dc²); between nodes,
//    dc/dθ interpolated like c and dσ_s/dθ at that c.
//  * A finite `cutoff` ends the sweep once the direction's partial sum of g reaches it.
//  * Warm starts (c* at every sample only): the local step's evaluations at nearby parameters
//    start each sample from the state the previous evaluation ended that sample in (its
//    SweepStates), so that they follow one branch of the tile's equilibria instead of
//    settling, from the rest state, in whichever of several nearby equilibria the path leads
//    to (the stockinette's warp at rest moved c* by 3e-4 for a 0.1 % change of ks1 from the rest
//    state, by 1e-7 along the branch).

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "fabrics_db/targets/uniform_targets.hpp"
#include "yarn_fit/homogenise/readouts.hpp"
#include "yarn_fit/model/yarn_params.hpp"
#include "yarn_fit/periodic/yarn_system.hpp"

namespace yarnfit::yarn {

// The second Piola–Kirchhoff stress of a uniaxial sample from its nominal stress and stretch.
inline double pk2(double stress, double stretch) { return stress / (1.0 + stretch); }

// The fixed comfort-range facts of one direction's targets.
struct DirectionScale {
  db::Direction direction = db::Direction::weft;
  double comfort_stretch = 0.0;   // end of the comfort range
  double comfort_value = 0.0;     // v_comfort: target S at comfort_stretch [N/m]
  double stress_norm = 0.0;       // largest target S in the comfort range [N/m]
  double compression_norm = 0.0;  // largest target |c| in the comfort range (≥ min norm)
  double compression_weight = 1.0;  // the compression terms' weight beside the stress terms'

};

// Where a sweep left each sample: the equilibrium, its c and d²Ψ/dc² (0 when unknown).
struct SweepStates {
  std::vector<Eigen::VectorXd> g;
  std::vector<double> compression;
  std::vector<double> slope;
  [[nodiscard]] std::size_t size() const { return g.size(); }
};

struct DirectionError {
  DirectionScale scale;
  double value = 0.0;               // this direction's term of g
  double stress_comfort_pct = 0.0;
  double stress_full_pct = 0.0;
  double compression_pct = 0.0;
  std::vector<double> stretch;            // s_i
  std::vector<double> stress_sim;         // S_sim(s_i) [N/m], second Piola-Kirchhoff
  std::vector<double> stress_target;      // S_tgt(s_i)
  std::vector<double> compression_sim;    // interpolated (or solved) c*
  std::vector<double> compression_target;
  std::vector<double> weight;             // w_i
  // With parameters to differentiate by: dS_sim/dθ and dc_sim/dθ per sample (one entry per
  // parameter asked for), at the held rest state.
  std::vector<Eigen::VectorXd> d_stress_sim, d_compression_sim;
  int held = 0;  // samples with d²Ψ/dc² ≤ 0 or no sensitivities: c held where accepted (root_correction)
  int flat = 0;  // samples whose band was wider than ±flat_band
  SweepStates states;  // with SweepSettings::record_states
  int solves = 0;
  // The bending term (ObjectiveOptions::bending_weight > 0, bending targets of this direction):
  // Δσ_κ = σ_κ(κ_j) − σ_κ(0) at the bending samples against the targets' 2 k_θ κ_j, normalised
  // by the largest |target|; its share of `value` is bending_weight · mean_j error².
  std::vector<double> bending_curvature, bending_sim, bending_target;
  std::vector<Eigen::VectorXd> d_bending_sim;  // dΔσ_κ/dθ per bending sample, with derivatives
  double bending_norm = 0.0;
  double bending_weight = 0.0;
};

struct SweepSettings {
  int samples = 7;
  bool every_sample = true;  // c* at every sample; false: at `nodes` samples, linear between
  int nodes = 2;
  yarn::CompressionOptions compression;  // its stress_tolerance: the band, in N/m
  yarn::EquilibriumOptions solve;
  bool root_correction = true;
  double flat_band = 0.05;               // bands wider than ±this are counted flat
  // Sensitive searches stop once |∂Ψ/∂c| is within this many bands: the read-out is then moved
  // to the band to first order from that solve (1: stop only inside the band).
  double accept_bands = 1.0;
  std::span<const yarn::YarnParam> wanted;  // derivatives by these (empty: none)
  double cutoff = 0.0;                      // stop once the partial sum reaches it (≤ 0 or inf: never)
  const SweepStates* warm = nullptr;        // start sample i from warm's (c* at every sample only)
  bool record_states = false;               // keep where every sample ended (DirectionError::states)
};

// What a sweep adds to the objective's counts.
struct SweepCounts {
  int newton_iterations = 0;
  int loose_solves = 0;
  bool stopped = false;  // the cutoff was reached: e.value is a lower bound
};

// Linear interpolation of the targets' (stretch → value) at s, clamped to the ends.
double interpolate_target(const std::vector<db::UniaxialPoint>& points, double s, double db::UniaxialPoint::*field);

// Runs the direction's sweep on `system` (the rest state's, at χ = 0, with `g_rest` its state),
// filling `e` (whose scale must be set). Returns why it failed, empty when it did not.
std::string sweep_direction(yarn::YarnSystem& system, const Eigen::VectorXd& g_rest, const db::DirectionTargets& targets,
                            const SweepSettings& settings, DirectionError& e, SweepCounts& counts);

// The bending term of one direction (see DirectionError): from the rest state (`system` at
// χ = 0 with `g_rest`), bent about the direction's axis at `samples` curvatures evenly over the
// targets' range (the largest included), with derivatives by `wanted`. Appends to `e`, adds its
// share to e.value. Returns why it failed, empty when it did not.
std::string sweep_bending(yarn::YarnSystem& system, const Eigen::VectorXd& g_rest, const db::DirectionTargets& targets,
                          int samples, double weight, const yarn::EquilibriumOptions& solve,
                          std::span<const yarn::YarnParam> wanted, DirectionError& e, SweepCounts& counts);

}  // namespace yarnfit::yarn
