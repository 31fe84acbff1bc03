#include "yarn_fit/scenes/sample_json.hpp"

#include <cmath>
#include <sstream>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/clock.hpp"

namespace yarnfit::yarn {

namespace {

using nlohmann::json;
using numerics::Clock;

json number_or_null(bool ok, double v) { return ok && std::isfinite(v) ? json(v) : json(nullptr); }

std::string csv_number(bool ok, double v) { return ok && std::isfinite(v) ? db::format_g(v, 12) : std::string(); }

}  // namespace

std::string termination(const Sample& s) {
  // A good sample says how its last solve stopped: at the force tolerance ("converged") or
  // once the coarse stress had settled ("converged_readout", EquilibriumOptions::stress_tolerance).
  if (s.ok) return s.last_solve.converged() ? to_string(s.last_solve.status) : "converged";
  if (s.last_solve.converged()) return "compression_search";
  return to_string(s.last_solve.status);
}

SceneSample simulate_scene_sample(YarnScene& scene, const SceneSampleRequest& r) {
  auto& system = *scene.system;
  SceneSample out;
  out.g = scene.g;
  const auto start = Clock::now();
  out.chi = CoarseDeformation{r.stretch, r.compression, r.curvature, scene.angle};
  Sample& sample = out.sample;
  auto& bend = out.bend;
  if (r.free_compression) {
    sample = solve_free_compression(system, out.chi, out.g, scene.compression, scene.solve);
    out.newton_iterations += sample.newton_iterations;
    out.solves += sample.solves;
    if (sample.ok && r.bending) bend = simulate_bending(system, sample.chi, out.g, 0.0, scene.solve);
  } else if (r.bending) {
    bend = simulate_bending(system, out.chi, out.g, 0.0, scene.solve);
    sample = bend->centre;
  } else {
    sample = simulate_sample(system, out.chi, out.g, scene.solve);
    out.newton_iterations = sample.newton_iterations;
    out.solves = sample.solves;
  }
  if (bend) {
    out.newton_iterations += bend->centre.newton_iterations;
    out.solves += bend->centre.solves;
  }
  out.seconds = numerics::seconds_since(start);

  const bool rest_ok = !scene.rest || scene.rest->converged;
  const bool sample_ok = sample.ok && (!bend || bend->ok);
  out.ok = rest_ok && sample_ok;
  out.termination = termination(sample);
  if (!sample.ok) out.message = sample.message;
  else if (bend && !bend->ok) {
    out.termination = "bending_stencil";
    out.message = "bending stress: " + bend->message;
  }
  if (!rest_ok) {
    if (sample_ok) out.termination = std::string("rest_shape_") + to_string(scene.rest->last_solve.status);
    out.message = (out.message.empty() ? "" : out.message + "; ") + "rest shape: last solve " +
                  to_string(scene.rest->last_solve.status) + ": " + scene.rest->last_solve.message;
  }
  return out;
}

json sample_json(const YarnScene& scene, const SceneSampleRequest& r, const SceneSample& s, int threads,
                 double total_seconds) {
  const Sample& sample = s.sample;
  const auto& system = *scene.system;
  json out;
  out["pattern"] = scene.pattern_file;
  out["direction"] = scene.direction;
  out["angle_rad"] = scene.angle;
  out["stretch"] = r.stretch;
  out["compression_mode"] = r.free_compression ? "free" : "fixed";
  if (r.free_compression) out["compression_method"] = to_string(scene.compression.method);
  out["curvature"] = r.curvature;
  out["energy_density"] = number_or_null(sample.ok, sample.energy_density);
  out["stress_s"] = number_or_null(sample.ok, sample.stress_s);
  out["stress_c"] = number_or_null(sample.ok, sample.stress_c);
  out["compression"] = r.free_compression ? number_or_null(sample.ok, sample.chi.compression) : json(r.compression);
  if (sample.ok && !s.chi.curved()) {
    const auto& p = sample.coarse_stress;
    out["coarse_stress"] = json::array({json::array({p(0, 0), p(0, 1)}), json::array({p(1, 0), p(1, 1)})});
  }
  if (r.bending) {
    out["stress_kappa"] = number_or_null(s.bend && s.bend->ok, s.bend ? s.bend->stress_kappa : 0.0);
    out["bending_step_per_m"] = 1e-3 / system.tile().radius;
  }
  out["converged"] = s.ok;
  out["termination"] = s.termination;
  out["message"] = s.message;
  out["newton_iterations"] = s.newton_iterations;
  out["solves"] = s.solves;
  out["seconds"] = s.seconds;
  out["residual_N"] = sample.last_solve.residual;
  out["tolerance_N"] = sample.last_solve.tolerance;
  out["min_contact_distance_m"] = sample.last_solve.min_contact_distance;
  out["effects"] = s.sample.effects;  // the terms assembled, and co-rotation when curved
  out["rest_shape"] = rest_shape_json(scene);
  out["params"] = to_json(scene.params);
  out["tile"] = tile_json(scene);
  out["threads"] = threads;
  out["total_seconds"] = total_seconds;
  out["units"] = units_json();
  return out;
}

std::string sweep_csv(const std::string& direction, const StretchSweep& sweep) {
  std::ostringstream csv;
  csv << "direction,stretch,compression,energy_density_J_per_m2,stress_s_N_per_m,converged,newton_iterations,seconds,"
         "solves,stress_c_N_per_m,termination,compression_band_lower,compression_band_upper,flat\n";
  for (const auto& s : sweep.points) {
    // The band where the orthogonal stress is within the read-out tolerance; flat = 1: Ψ is
    // flat in c over it and c is the band's point of smallest |c| (readouts.hpp).
    const bool band = s.ok && std::isfinite(s.band_lower) && std::isfinite(s.band_upper);
    csv << direction << "," << db::format_g(s.chi.stretch, 12) << "," << csv_number(s.ok, s.chi.compression) << ","
        << csv_number(s.ok, s.energy_density) << "," << csv_number(s.ok, s.stress_s) << "," << (s.ok ? 1 : 0) << ","
        << s.newton_iterations << "," << db::format_g(s.seconds, 6) << "," << s.solves << ","
        << csv_number(s.ok, s.stress_c) << "," << termination(s) << "," << csv_number(band, s.band_lower) << ","
        << csv_number(band, s.band_upper) << "," << (s.ok && s.flat ? 1 : 0) << "\n";
  }
  return csv.str();
}

}  // namespace yarnfit::yarn
