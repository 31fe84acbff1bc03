#pragma once
// The error figures yarnfit reports (SPEC §3 "Error metrics reported"), written once so that
// the fits, `yarnfit fit` and the summaries print the same numbers the thesis compares. They
// sit in results/ because the result files carry them (per direction too, computed once by the
// fit, or on reading an older file that did not store them):
//
//   shell (Fig. 6.13)  100 · mean_i |sim_i − meas_i| / mean_i |meas_i|      [%]
//                      over every target of the curves taken together (force, compression
//                      and aspect ratio each on their own), i.e. 100 · Σ|sim − meas| / Σ|meas|;
//   yarn (Fig. 6.15, Table 6.1)
//                      100 · mean_i |sim_i − target_i| / norm               [%]
//                      with norm the largest target in the comfort range (stress over the
//                      comfort range, stress over the full range, compression; the bending
//                      check uses the largest bending target), per direction; the overall
//                      figure is the mean over directions.
//
// NaN means "no figure": nothing measured, a curve whose simulation is missing or has another
// length, a NaN value, or a non-positive norm. It is never 0: a fit whose final evaluation
// failed has no errors, and its JSON says null (pct_json). The arithmetic order of each
// function is part of its contract (the figures are compared bit for bit across versions).

#include <cstddef>
#include <span>

#include <nlohmann/json.hpp>

namespace yarnfit::results {

// The shell metric summed over several curves: add each curve's measured and simulated values
// (same points, same order), then read pct().
class ShellErrorSum {
 public:
  // Adds Σ|simulated_i − measured_i| and Σ|measured_i| in order i = 0, 1, …. Curves of
  // different lengths make the sum unusable (pct() NaN).
  void add(std::span<const double> measured, std::span<const double> simulated);
  // 100 · Σ|sim − meas| / Σ|meas|; NaN when Σ|meas| is not positive or any value was NaN.
  [[nodiscard]] double pct() const;

 private:
  double m_error = 0.0;
  double m_measured = 0.0;
  bool m_mismatch = false;
};

// The shell metric of one curve.
[[nodiscard]] double shell_error_pct(std::span<const double> measured, std::span<const double> simulated);

// The yarn metric of one direction: Σ_i |(simulated_i − target_i) / norm| summed in order, then
// 100 · sum / n (each difference is normalised first, as the objective's residuals are).
// NaN for no samples, different lengths or norm not positive.
[[nodiscard]] double yarn_error_pct(std::span<const double> simulated, std::span<const double> target, double norm);
// The same metric normalised after the mean: 100 · Σ|simulated_i − target_i| / n / norm, the
// bending check's order (kept so its figures stay the same to the last bit).
[[nodiscard]] double yarn_error_pct_normalised_after(std::span<const double> simulated,
                                                     std::span<const double> target, double norm);

// The overall yarn figure: Σ per_direction / n, summed in order; NaN when empty or any is NaN.
[[nodiscard]] double mean_over_directions(std::span<const double> per_direction);

// A figure for JSON: the number, or null when it is NaN or infinite.
[[nodiscard]] nlohmann::json pct_json(double pct);
// A figure back from JSON: the number, or NaN for null or anything else.
[[nodiscard]] double number_or_nan(const nlohmann::json& value);

}  // namespace yarnfit::results
