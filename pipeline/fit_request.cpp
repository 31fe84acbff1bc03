#include "pipeline/fit_request.hpp"
#include "pipeline/fit_request_fields.hpp"

#include "yarn_fit/fit/budget.hpp"

namespace yarnfit::pipeline {

namespace {

shell::ShellFitOptions shell_options(const FitRequest& r, db::Problems& problems) {
  shell::ShellFitOptions o;
  if (const auto model = shell::parse_inplane_model(r.shell_model)) o.model = *model;
  else problems.add("", 0, "shell_model", r.shell_model + ": not a shell model (stiffening or thesis)");
  o.mesh = r.mesh_mm * 1e-3;
  o.refinements = r.refinements;
  o.threads = r.shell_threads ? *r.shell_threads : r.threads > 0 ? r.threads : 2;
  o.max_iterations = r.max_iterations;
  o.full_range = r.full_range;
  o.fab_held_out = r.fab_held_out;
  return o;
}

yarn::YarnFitSettings yarn_settings(const FitRequest& r, db::Problems& problems) {
  yarn::YarnFitSettings s;
  if (const auto global = yarn::global_method_from_string(r.global_method)) s.global_method = *global;
  else problems.add("", 0, "global_method", r.global_method + ": not a global method (staged or swarm)");
  if (const auto budget = yarn::budget_from_string(r.budget)) yarn::apply_budget(*budget, s);
  else problems.add("", 0, "budget", r.budget + ": not a budget (quick, default or thorough)");
  if (r.particles) s.particles = *r.particles;
  if (r.iterations) s.iterations = *r.iterations;
  if (r.samples) s.swarm_samples = *r.samples;
  if (r.local_samples) s.local_samples = *r.local_samples;
  if (r.local_evaluations) s.local_evaluations = *r.local_evaluations;
  if (r.starts) s.staged.starts = *r.starts;
  if (const auto method = yarn::local_method_from_string(r.local_method)) s.local_method = *method;
  else
    problems.add("", 0, "local_method",
                 r.local_method + ": not a local method (gauss-newton, implicit-filtering or cobyla)");
  s.seed = r.seed;
  s.threads = r.threads;
  s.swarm = !r.no_swarm && r.start.empty();
  s.linear_stretch = r.linear_stretch;
  s.rest_shape = !r.no_rest_shape;
  s.objective.rest_period = r.relax_period;
  s.objective.compression_weight = r.compression_weight;
  if (r.no_profile) s.profile_step = 0.0;
  s.swarm_compression_nodes = r.compression_nodes;
  s.local_compression_nodes = r.compression_nodes;
  s.checkpoint = r.checkpoint;
  s.resume = r.resume;
  return s;
}

}  // namespace

PipelineOptions pipeline_options(const FitRequest& request, db::Problems& problems) {
  PipelineOptions o;
  if (const auto stages = stages_from_string(request.stages)) o.stages = *stages;
  else problems.add("", 0, "stages", request.stages + ": not a set of stages (all, shell or yarn)");
  o.shell = shell_options(request, problems);
  o.yarn = yarn_settings(request, problems);
  o.shape.enabled = !request.no_shape;
  for (const std::string& name : request.exports) {
    if (const auto format = exports::export_format_from_string(name)) o.exports.push_back(*format);
    else problems.add("", 0, "export", name + ": not an export format (u3m, arcsim or table)");
  }
  o.targets = request.targets;
  o.start = request.start;
  return o;
}

const yarn::YarnFitSettings& default_request_settings() {
  static const yarn::YarnFitSettings settings = [] {
    db::Problems none;
    return pipeline_options(FitRequest{}, none).yarn;
  }();
  return settings;
}

FitPlan fit_plan(const FitRequest& request, db::Problems& problems) {
  FitPlan plan;
  plan.fabric = request.fabric;
  plan.out = request.out;
  plan.options = pipeline_options(request, problems);
  plan.report = request.report;
  plan.overwrite = request.overwrite || request.resume;
  return plan;
}

}  // namespace yarnfit::pipeline
