#include "batch/batch_options.hpp"

#ifndef YARNFIT_VERSION
#define YARNFIT_VERSION "0.0.0"
#endif

namespace yarnfit::batch {

namespace fs = std::filesystem;

db::Problems BatchOptions::problems() const {
  db::Problems found;
  const auto say = [&found](const char* field, const std::string& message) { found.add("", 0, field, message); };
  if (database.empty() && !feed) say("database", "no database folder given");
  else if (!database.empty() && !fs::is_directory(database)) say("database", database.string() + ": not a folder");
  if (out.empty()) say("out", "no output folder given");
  else if (fs::exists(this->out) && !fs::is_directory(this->out)) say("out", this->out.string() + ": exists and is not a folder");
  if (jobs < 1 || jobs > 256) say("jobs", "must be 1-256 (got " + std::to_string(jobs) + ")");
  if (threads_per_job < 1 || threads_per_job > 256)
    say("threads_per_job", "must be 1-256 (got " + std::to_string(threads_per_job) + ")");
  if (!(heartbeat_interval > 0)) say("heartbeat_interval", "must be positive");
  if (!(stale_after > heartbeat_interval)) say("stale_after", "must exceed the heartbeat interval");
  if (fit.stages == pipeline::Stage::yarn)
    say("stages", "yarn: a batch runs shell or all (the yarn stage alone fits a targets file, not a database)");
  const db::Problems fit_problems = fit.problems();
  for (const auto& p : fit_problems.items()) found.add(p.file, p.line, "fit." + p.field, p.message);
  return found;
}

nlohmann::json fit_options_json(const pipeline::PipelineOptions& o) {
  nlohmann::json j;
  j["yarnfit_version"] = YARNFIT_VERSION;
  j["stages"] = pipeline::to_string(o.stages);
  j["shell"] = {{"mesh", o.shell.mesh},
                {"refinements", o.shell.refinements},
                {"max_iterations", o.shell.max_iterations},
                {"full_range", o.shell.full_range},
                {"fab_held_out", o.shell.fab_held_out},
                {"model", shell::to_string(o.shell.model)}};
  if (o.stages == pipeline::Stage::shell) return j;
  const auto& y = o.yarn;
  j["yarn"] = {{"particles", y.particles},
               {"iterations", y.iterations},
               {"swarm_samples", y.swarm_samples},
               {"local_samples", y.local_samples},
               {"swarm_compression_nodes", y.swarm_compression_nodes},
               {"local_compression_nodes", y.local_compression_nodes},
               {"seed", y.seed},
               {"swarm", y.swarm},
               {"linear_stretch", y.linear_stretch},
               {"rest_shape", y.rest_shape},
               {"swarm_cutoff", y.swarm_cutoff},
               {"local_method", yarn::to_string(y.local_method)},
               {"local_evaluations", y.local_evaluations},
               {"local_initial_step", y.local_initial_step},
               {"local_initial_scale", y.local_initial_scale},
               {"local_min_scale", y.local_min_scale},
               {"bending_points", y.bending_points},
               {"profile_step", y.profile_step},
               {"global_method", yarn::to_string(y.global_method)},
               {"staged",
                {y.staged.contact.particles, y.staged.contact.iterations, y.staged.contact.samples,
                 y.staged.all.particles, y.staged.all.iterations, y.staged.all.samples, y.staged.r1_window,
                 y.staged.rescored, y.staged.distinct, y.staged.starts}},
               {"alternation",
                {y.alternation.max_rounds, y.alternation.iterations_per_round, y.alternation.initial_radius,
                 y.alternation.secant_move, y.alternation.move_tolerance, y.alternation.failures_before_fallback,
                 y.alternation.rest_difference_step}},
               {"band_correction", y.objective.root_correction}};
  return j;
}

fs::path fabric_output_folder(const fs::path& out, const std::string& fabric_id) { return out / "fabrics" / fabric_id; }
fs::path swarm_checkpoint_file(const fs::path& fabric_folder) { return fabric_folder / "swarm_checkpoint.json"; }
fs::path ledger_file(const fs::path& out) { return out / "batch.db"; }
fs::path generated_tiles_folder(const fs::path& out) { return out / "tiles"; }

}  // namespace yarnfit::batch
