#include "results/yarn_fit_file.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "results/json_fields.hpp"
#include "results/metrics/error_metrics.hpp"
#include "numerics/util/non_finite.hpp"

namespace yarnfit::results {

using nlohmann::json;
using namespace detail;

namespace {

using numerics::k_nan;

// ------------------------------------------------------------------------------ errors, curves

// One direction's errors (bending_pct and curl_stress_kappa_N, written only when there are
// some, are direction_json's and read_direction's own) and one direction's curves.
template <class Fields, class Errors>
void direction_fields(Fields& f, Errors& d) {
  f("stress_comfort_pct", d.stress_comfort_pct, k_nan);
  f("stress_full_pct", d.stress_full_pct, k_nan);
  f("compression_pct", d.compression_pct, k_nan);
  f("comfort_stretch", d.comfort_stretch, k_nan);
  f("objective", d.objective, k_nan);
  f("samples", d.samples, 0LL);
  f("flat_compressions", d.flat_compressions, 0);
  f("held_compressions", d.held_compressions, 0);
}

template <class Fields, class Curve>
void curve_fields(Fields& f, Curve& c) {
  f("direction", c.direction, std::string("?"));
  f("stretch", c.stretch, std::vector<double>());
  f("target_S_N_per_m", c.target_S_N_per_m, std::vector<double>());
  f("simulated_S_N_per_m", c.simulated_S_N_per_m, std::vector<double>());
  f("target_compression", c.target_compression, std::vector<double>());
  f("simulated_compression", c.simulated_compression, std::vector<double>());
  f("weight", c.weight, std::vector<double>());
}

json direction_json(const YarnDirectionErrors& d) {
  json j = fields_json(d, [](auto& f, auto& r) { direction_fields(f, r); });
  if (d.bending_pct) j["bending_pct"] = pct_json(*d.bending_pct);
  if (d.curl_stress_kappa_N) j["curl_stress_kappa_N"] = pct_json(*d.curl_stress_kappa_N);
  return j;
}

YarnDirectionErrors read_direction(const json& e, const Where& w) {
  auto d = read_fields<YarnDirectionErrors>(e, w, [](auto& f, auto& r) { direction_fields(f, r); });
  if (member(e, "bending_pct")) d.bending_pct = number(e, "bending_pct", w, k_nan);
  if (member(e, "curl_stress_kappa_N")) d.curl_stress_kappa_N = number(e, "curl_stress_kappa_N", w, k_nan);
  return d;
}

json curve_json(const YarnCurve& c) {
  return fields_json(c, [](auto& f, auto& r) { curve_fields(f, r); });
}

YarnCurve read_curve(const json& c, const Where& w) {
  return read_fields<YarnCurve>(c, w, [](auto& f, auto& r) { curve_fields(f, r); });
}

// ------------------------------------------------------------------------------ identifiability

json identifiability_json(const Identifiability& p) {
  json entries = json::object();
  for (const auto& [name, e] : p.parameters)
    entries[name] = {{"value", e.value},
                     {"objective_lower", pct_json(e.objective_lower)},
                     {"objective_upper", pct_json(e.objective_upper)},
                     {"range_factor", pct_json(e.range_factor)},
                     {"range_alone_factor", pct_json(e.range_alone_factor)},
                     {"free", e.free},
                     {"free_alone", e.free_alone}};
  json j = {{"computed", p.computed}, {"from", p.from},           {"step", p.step},
            {"objective", pct_json(p.objective)}, {"parameters", entries}, {"evaluations", p.evaluations},
            {"seconds", p.seconds}};
  if (!p.message.empty()) j["message"] = p.message;
  return j;
}

Identifiability read_identifiability(const json& p, const Where& at) {
  expect_object(p, at);
  Identifiability out;
  out.computed = boolean(p, "computed", at, false);
  out.from = string(p, "from", at);
  out.message = string(p, "message", at);
  out.step = number(p, "step", at, k_nan);
  out.objective = number(p, "objective", at, k_nan);
  const json& entries = object_or_empty(p, "parameters", at);
  for (const auto& [name, e] : entries.items()) {
    const Where w = at / "parameters" / name;
    expect_object(e, w);
    out.parameters[name] = {number(e, "value", w, k_nan),          number(e, "objective_lower", w, k_nan),
                            number(e, "objective_upper", w, k_nan),  number(e, "range_factor", w, k_nan),
                            number(e, "range_alone_factor", w, k_nan), boolean(e, "free", w, false),
                            boolean(e, "free_alone", w, false)};
  }
  out.evaluations = integer(p, "evaluations", at, 0);
  out.seconds = number(p, "seconds", at, k_nan);
  return out;
}

// ------------------------------------------------------------------------------ settings

template <class Fields, class Stage>
void stage_settings_fields(Fields& f, Stage& s) {
  f("particles", s.particles, 0);
  f("iterations", s.iterations, 0);
  f("samples", s.samples, 0);
}

// The settings' fields, each with the value a file without it (an older version) reads as.
// `start`, `resumed_from` and `alternation.rest_difference_step` are written only when there is
// one: they are settings_json's and read_settings' own.
template <class Fields, class Settings>
void settings_fields(Fields& f, Settings& s) {
  f("global_method", s.global_method, std::string("swarm"));  // the only method before the staged search
  f.object("staged", [&](auto& staged) {
    staged.object("contact", [&](auto& c) { stage_settings_fields(c, s.staged_contact); });
    staged.object("all", [&](auto& a) { stage_settings_fields(a, s.staged_all); });
    staged("r1_window", s.staged_r1_window, k_nan);
    staged("rescored", s.staged_rescored, 0);
    staged("starts", s.staged_starts, 0);
  });
  f.object("alternation", [&](auto& a) {
    a("max_rounds", s.alternation_max_rounds, 0);
    a("iterations_per_round", s.alternation_iterations_per_round, 0);
    a("initial_radius", s.alternation_initial_radius, k_nan);
    a("move_tolerance", s.alternation_move_tolerance, k_nan);
  });
  f("particles", s.particles, 0);
  f("iterations", s.iterations, 0);
  f("swarm_samples", s.swarm_samples, 0);
  f("local_samples", s.local_samples, 0);
  f("local_method", s.local_method, std::string("?"));
  f("local_evaluations", s.local_evaluations, 0);
  f("swarm_compression_nodes", s.swarm_compression_nodes, 0);
  f("local_compression_nodes", s.local_compression_nodes, 0);
  f("seed", s.seed, std::uint64_t{0});
  f("swarm", s.swarm, true);
  f("linear_stretch", s.linear_stretch, false);
  f("rest_shape", s.rest_shape, true);
  f("rest_period", s.rest_period, false);
  f("band_correction", s.band_correction, false);
  f("bending_points", s.bending_points, 0);
  f("profile_step", s.profile_step, k_nan);
  f("swarm_cutoff", s.swarm_cutoff, true);
}

json settings_json(const YarnFitSettingsRecord& s) {
  json j = json::object();
  FieldWriter w(j);
  settings_fields(w, s);
  if (s.start) j["start"] = *s.start;
  if (!s.resumed_from.empty()) j["resumed_from"] = s.resumed_from;
  // Since issue 49; absent (NaN on reading) in older files, which write back as they were.
  if (std::isfinite(s.alternation_rest_difference_step))
    j["alternation"]["rest_difference_step"] = s.alternation_rest_difference_step;
  return j;
}

YarnFitSettingsRecord read_settings(const json& s, const Where& at) {
  YarnFitSettingsRecord r;
  const FieldReader f(s, at);
  settings_fields(f, r);
  r.alternation_rest_difference_step =
      number(object_or_empty(s, "alternation", at), "rest_difference_step", at / "alternation", k_nan);
  if (member(s, "start")) r.start = number_map(s, "start", at);
  r.resumed_from = string(s, "resumed_from", at);
  return r;
}

// ------------------------------------------------------------------------------ search records

json swarm_json(const SwarmRecord& s) {
  json history = json::array();
  for (const auto& h : s.history)
    history.push_back({{"iteration", h.iteration}, {"best", pct_json(h.best)}, {"failed", h.failed}});
  return {{"best", pct_json(s.best)},
          {"evaluations", s.evaluations},
          {"failed", s.failed},
          {"stopped_at_cutoff", s.stopped_at_cutoff},
          {"history", history},
          {"report", s.report}};
}

SwarmRecord read_swarm(const json& s, const Where& at) {
  expect_object(s, at);
  SwarmRecord r{number(s, "best", at, k_nan), integer(s, "evaluations", at, 0), integer(s, "failed", at, 0),
                integer(s, "stopped_at_cutoff", at, 0), {}, string(s, "report", at)};
  for_each_object(s, "history", at, [&r](const json& h, const Where& w) {
    r.history.push_back({integer(h, "iteration", w, 0), number(h, "best", w, k_nan), integer(h, "failed", w, 0)});
  });
  return r;
}

json global_json(const GlobalRecord& g) {
  json stages = json::array();
  for (const auto& st : g.stages)
    stages.push_back({{"stage", st.stage},
                      {"evaluations", st.evaluations},
                      {"stopped_at_cutoff", st.stopped_at_cutoff},
                      {"best", pct_json(st.best)},
                      {"seconds", st.seconds},
                      {"report", st.report}});
  return {{"method", g.method}, {"stages", stages}};
}

GlobalRecord read_global(const json& g, const Where& at) {
  expect_object(g, at);
  GlobalRecord r{string(g, "method", at), {}};
  for_each_object(g, "stages", at, [&r](const json& st, const Where& w) {
    r.stages.push_back({string(st, "stage", w), integer(st, "evaluations", w, 0), integer(st, "stopped_at_cutoff", w, 0),
                        number(st, "best", w, k_nan), number(st, "seconds", w, k_nan), string(st, "report", w)});
  });
  return r;
}

json local_run_json(const LocalRunRecord& l) {
  json j = {{"method", l.method},      {"status", l.status},          {"converged", l.converged},
            {"best", pct_json(l.best)}, {"start", pct_json(l.start)}, {"evaluations", l.evaluations},
            {"failed", l.failed},      {"seconds", l.seconds},        {"report", l.report}};
  if (l.iterations) j["iterations"] = *l.iterations;
  if (l.final_scale) j["final_scale"] = *l.final_scale;
  if (l.history) {
    json history = json::array();
    for (const auto& h : *l.history)
      history.push_back({{"evaluations", h.evaluations},
                         {"scale", h.scale},
                         {"best", h.best},
                         {"move", h.move},
                         {"trials", h.trials}});
    j["history"] = history;
  }
  if (l.rounds) {
    json rounds = json::array();
    for (const auto& r : *l.rounds) {
      json round = {{"round", r.round},
                        {"objective_start", pct_json(r.objective_start)},
                        {"objective_held", pct_json(r.objective_held)},
                        {"objective_trial", pct_json(r.objective_trial)},
                        {"accepted", r.accepted},
                        {"move", r.move},
                        {"iterations", r.iterations},
                        {"evaluations", r.evaluations},
                        {"termination", r.termination}};
      if (r.rest_derivative_measured) round["rest_derivative_measured"] = true;  // absent: false (older files)
      rounds.push_back(round);
    }
    j["rounds"] = rounds;
  }
  if (l.last_move) j["last_move"] = *l.last_move;
  if (l.fell_back) j["fell_back"] = *l.fell_back;
  if (l.fallback) j["fallback"] = {{"reason", l.fallback->reason}, {"report", l.fallback->report}};
  return j;
}

LocalRunRecord read_local_run(const json& l, const Where& at) {
  expect_object(l, at);
  LocalRunRecord r;
  r.method = string(l, "method", at);
  r.status = string(l, "status", at);
  r.converged = boolean(l, "converged", at, false);
  r.best = number(l, "best", at, k_nan);
  r.start = number(l, "start", at, k_nan);
  r.evaluations = integer(l, "evaluations", at, 0);
  r.failed = integer(l, "failed", at, 0);
  r.seconds = number(l, "seconds", at, k_nan);
  r.report = string(l, "report", at);
  if (member(l, "iterations")) r.iterations = integer(l, "iterations", at, 0);
  if (member(l, "final_scale")) r.final_scale = number(l, "final_scale", at, k_nan);
  if (member(l, "history")) {
    r.history.emplace();
    for_each_object(l, "history", at, [&r](const json& h, const Where& w) {
      r.history->push_back({integer(h, "evaluations", w, 0), number(h, "scale", w, k_nan), number(h, "best", w, k_nan),
                            string(h, "move", w), integer(h, "trials", w, 0)});
    });
  }
  if (member(l, "rounds")) {
    r.rounds.emplace();
    for_each_object(l, "rounds", at, [&r](const json& x, const Where& w) {
      r.rounds->push_back({integer(x, "round", w, 0), number(x, "objective_start", w, k_nan),
                           number(x, "objective_held", w, k_nan), number(x, "objective_trial", w, k_nan),
                           boolean(x, "accepted", w, false), number(x, "move", w, k_nan), integer(x, "iterations", w, 0),
                           integer(x, "evaluations", w, 0), string(x, "termination", w),
                           boolean(x, "rest_derivative_measured", w, false)});
    });
  }
  if (member(l, "last_move")) r.last_move = number(l, "last_move", at, k_nan);
  if (member(l, "fell_back")) r.fell_back = boolean(l, "fell_back", at, false);
  if (member(l, "fallback")) {
    const json& f = object_or_empty(l, "fallback", at);
    r.fallback = LocalFallback{string(f, "reason", at / "fallback"), string(f, "report", at / "fallback")};
  }
  return r;
}

}  // namespace

YarnDirectionErrors YarnDirectionErrors::none() {
  YarnDirectionErrors d;
  d.stress_comfort_pct = d.stress_full_pct = d.compression_pct = d.comfort_stretch = d.objective = k_nan;
  return d;
}

json direction_errors_json(const std::map<std::string, YarnDirectionErrors>& errors) {
  json dirs = json::object();
  for (const auto& [name, d] : errors) dirs[name] = direction_json(d);
  return dirs;
}

std::map<std::string, double> named_errors(const YarnErrors& e) {
  return {{"stress_comfort_pct", e.stress_comfort_pct},
          {"stress_full_pct", e.stress_full_pct},
          {"compression_pct", e.compression_pct},
          {"bending_pct", e.bending_pct}};
}

std::map<std::string, double> named_times(const YarnTiming& t) {
  return {{"swarm", t.swarm}, {"local", t.local}, {"bending_check", t.bending_check}, {"profile", t.profile},
          {"total", t.total}};
}

// The shape search's record: the aspect, its prior and bounds, and every trial.
json shape_json(const ShapeRecord& sh) {
  json trials = json::array();
  for (const auto& t : sh.trials)
    trials.push_back({{"aspect", t.aspect},
                      {"held", t.held},
                      {"objective", pct_json(t.objective)},
                      {"r1_m", t.r1_m},
                      {"full_fit", t.full_fit},
                      {"seconds", t.seconds},
                      {"message", t.message}});
  return {{"aspect", sh.aspect},
          {"held", sh.held},
          {"prior", sh.prior},
          {"prior_source", sh.prior_source},
          {"bounds", {{"lower", sh.lower}, {"upper", sh.upper}}},
          {"range", {pct_json(sh.range_lower), pct_json(sh.range_upper)}},
          {"wale_spacing_mm", sh.wale_spacing_mm},
          {"course_spacing_mm", sh.course_spacing_mm},
          {"wales_per_10cm", 100.0 / sh.wale_spacing_mm},
          {"courses_per_10cm", 100.0 / sh.course_spacing_mm},
          {"trials", trials},
          {"seconds", sh.seconds}};
}

// The tile the fit ran on: where it came from, its period and gauge, and the record's gauge.
json fitted_tile_json(const FittedTileRecord& t) {
  json tile = {{"source", t.source},
               {"period_mm", {{"weft", t.period_weft_mm}, {"warp", t.period_warp_mm}}},
               {"yarn_radius_mm", t.yarn_radius_mm},
               {"wales", t.wales},
               {"courses", t.courses},
               {"wales_per_10cm", pct_json(t.wales_per_10cm)},
               {"courses_per_10cm", pct_json(t.courses_per_10cm)}};
  if (t.record_wales_per_10cm && t.record_courses_per_10cm)
    tile["record_gauge"] = {{"wales_per_10cm", *t.record_wales_per_10cm}, {"courses_per_10cm", *t.record_courses_per_10cm}};
  return tile;
}

// The check against the record's measured curves: its errors, and the homogenised law fitted
// through the fitted yarn model's curves.
void add_measured_json(json& j, const MeasuredCheckRecord& m) {
  json vs = direction_errors_json(m.by_direction);
  vs["all"] = {{"stretch_force_pct", pct_json(m.all.stretch_force_pct)},
               {"compression_pct", pct_json(m.all.compression_pct)},
               {"bending_pct", pct_json(m.all.bending_pct)}};
  j["errors_vs_measured"] = vs;
  json law_curves = json::array(), bending = json::array();
  for (const auto& c : m.curves) law_curves.push_back(curves_json(c));
  for (const auto& c : m.bending_curves) bending.push_back(bending_curve_json(c));
  j["homogenised_law"] = {{"ok", m.ok},
                          {"message", m.message},
                          {"model", m.law_model},
                          {"params", m.law_params},
                          {"misfit_pct",
                           {{"stress", pct_json(m.law_stress_misfit_pct)},
                            {"compression", pct_json(m.law_compression_misfit_pct)},
                            {"bending", pct_json(m.law_bending_misfit_pct)}}},
                          {"curves", law_curves},
                          {"bending_curves", bending},
                          {"seconds", m.seconds}};
}

json to_json(const YarnFitFile& f) {
  json errors = json::object();
  for (const auto& [name, v] : named_errors(f.errors)) errors[name] = pct_json(v);
  json curves = json::array();
  for (const auto& c : f.curves) curves.push_back(curve_json(c));
  json timing = json::object();
  for (const auto& [name, v] : named_times(f.timing_s)) timing[name] = v;
  json j = {{"schema_version", k_yarn_fit_schema_version},
            {"fabric", f.fabric},
            {"family", f.family},
            {"targets", f.targets},
            {"ok", f.ok},
            {"params", f.params},
            {"errors", errors},
            {"errors_by_direction", direction_errors_json(f.errors_by_direction)},
            {"errors_reason", string_or_null(f.errors_reason)},
            {"curves", curves},
            {"effects", f.effects},
            {"bounds", bounds_json(f.bounds)},
            {"objective", pct_json(f.objective)},
            {"on_bound", f.on_bound},
            {"evaluations", f.evaluations},
            {"timing_s", timing},
            {"settings", settings_json(f.settings)}};
  if (!f.message.empty()) j["message"] = f.message;
  if (f.bending_check) j["bending_check"] = {{"ok", f.bending_check->ok}, {"message", f.bending_check->message}};
  if (f.identifiability) j["identifiability"] = identifiability_json(*f.identifiability);
  if (f.swarm) j["swarm"] = swarm_json(*f.swarm);
  if (f.global) j["global"] = global_json(*f.global);
  if (f.shape) j["shape"] = shape_json(*f.shape);
  if (f.tile) j["tile"] = fitted_tile_json(*f.tile);
  if (f.measured) add_measured_json(j, *f.measured);
  if (f.local) {
    j["local"] = local_run_json(f.local->best);
    json runs = json::array();
    for (const auto& run : f.local->runs) runs.push_back(local_run_json(run));
    j["local"]["runs"] = runs;
  }
  return j;
}

ShapeRecord read_shape(const json& j, const Where& w) {
  expect_object(j, w);
  ShapeRecord sh;
  sh.aspect = number(j, "aspect", w, k_nan);
  sh.held = boolean(j, "held", w, false);
  sh.prior = number(j, "prior", w, k_nan);
  sh.prior_source = string(j, "prior_source", w);
  const json& bounds = object_or_empty(j, "bounds", w);
  sh.lower = number(bounds, "lower", w / "bounds", k_nan);
  sh.upper = number(bounds, "upper", w / "bounds", k_nan);
  const std::vector<double> range = numbers(j, "range", w);
  sh.range_lower = range.size() == 2 ? range[0] : k_nan;
  sh.range_upper = range.size() == 2 ? range[1] : k_nan;
  sh.wale_spacing_mm = number(j, "wale_spacing_mm", w, k_nan);
  sh.course_spacing_mm = number(j, "course_spacing_mm", w, k_nan);
  for_each_object(j, "trials", w, [&sh](const json& x, const Where& wx) {
    sh.trials.push_back({number(x, "aspect", wx, k_nan), boolean(x, "held", wx, true), number(x, "objective", wx, k_nan),
                         number(x, "r1_m", wx, k_nan),
                         boolean(x, "full_fit", wx, false), number(x, "seconds", wx, k_nan), string(x, "message", wx)});
  });
  sh.seconds = number(j, "seconds", w, k_nan);
  return sh;
}

FittedTileRecord read_fitted_tile(const json& j, const Where& w) {
  expect_object(j, w);
  FittedTileRecord ft;
  ft.source = string(j, "source", w);
  const json& period = object_or_empty(j, "period_mm", w);
  ft.period_weft_mm = number(period, "weft", w / "period_mm", k_nan);
  ft.period_warp_mm = number(period, "warp", w / "period_mm", k_nan);
  ft.yarn_radius_mm = number(j, "yarn_radius_mm", w, k_nan);
  ft.wales = static_cast<int>(number(j, "wales", w, 0.0));
  ft.courses = static_cast<int>(number(j, "courses", w, 0.0));
  ft.wales_per_10cm = number(j, "wales_per_10cm", w, k_nan);
  ft.courses_per_10cm = number(j, "courses_per_10cm", w, k_nan);
  if (const json* g = member(j, "record_gauge")) {
    const Where wg = w / "record_gauge";
    expect_object(*g, wg);
    ft.record_wales_per_10cm = number(*g, "wales_per_10cm", wg, k_nan);
    ft.record_courses_per_10cm = number(*g, "courses_per_10cm", wg, k_nan);
  }
  return ft;
}

// The measured check: `law` is the file's homogenised_law, and its errors are the file's
// errors_vs_measured beside it.
MeasuredCheckRecord read_measured(const json& j, const json& law, const Where& at) {
  const Where w = at / "homogenised_law";
  expect_object(law, w);
  MeasuredCheckRecord m;
  m.ok = boolean(law, "ok", w, false);
  m.message = string(law, "message", w);
  m.law_model = string(law, "model", w);
  m.law_params = number_map(law, "params", w);
  const json& misfit = object_or_empty(law, "misfit_pct", w);
  m.law_stress_misfit_pct = number(misfit, "stress", w / "misfit_pct", k_nan);
  m.law_compression_misfit_pct = number(misfit, "compression", w / "misfit_pct", k_nan);
  m.law_bending_misfit_pct = number(misfit, "bending", w / "misfit_pct", k_nan);
  for_each_object(law, "curves", w, [&m](const json& c, const Where& wc) { m.curves.push_back(read_curves(c, wc)); });
  for_each_object(law, "bending_curves", w,
                  [&m](const json& c, const Where& wc) { m.bending_curves.push_back(read_bending_curve(c, wc)); });
  m.seconds = number(law, "seconds", w, k_nan);
  for (const auto& [name, e] : object_or_empty(j, "errors_vs_measured", at).items()) {
    const ShellDirectionErrors read = read_shell_errors(e, at / "errors_vs_measured" / name);
    if (name == "all") m.all = {read.stretch_force_pct, read.compression_pct, read.bending_pct};
    else m.by_direction[name] = read;
  }
  return m;
}

YarnFitFile yarn_fit_file_from_json(const json& j, const std::string& source) {
  const Where at(source);
  YarnFitFile f = open_result<YarnFitFile>(j, at, k_yarn_fit_schema_version);
  f.fabric = string(j, "fabric", at);
  f.family = string(j, "family", at);
  f.targets = string(j, "targets", at);
  f.ok = boolean(j, "ok", at, false);
  f.message = string(j, "message", at);
  if (!member(j, "params")) at.bad("params (the fitted parameters)");
  f.params = number_map(j, "params", at);
  const json& errors = object_or_empty(j, "errors", at);
  const Where we = at / "errors";
  f.errors = {number(errors, "stress_comfort_pct", we, k_nan), number(errors, "stress_full_pct", we, k_nan),
              number(errors, "compression_pct", we, k_nan), number(errors, "bending_pct", we, k_nan)};
  for (const auto& [name, e] : object_or_empty(j, "errors_by_direction", at).items())
    f.errors_by_direction[name] = read_direction(e, at / "errors_by_direction" / name);
  f.errors_reason = string(j, "errors_reason", at);
  for_each_object(j, "curves", at, [&f](const json& c, const Where& w) { f.curves.push_back(read_curve(c, w)); });
  f.effects = strings(j, "effects", at);
  f.bounds = read_bounds(j, at);
  if (const json* check = member(j, "bending_check")) {
    expect_object(*check, at / "bending_check");
    f.bending_check = CheckOutcome{boolean(*check, "ok", at / "bending_check", true),
                                   string(*check, "message", at / "bending_check")};
  }
  f.objective = number(j, "objective", at, k_nan);
  f.on_bound = strings(j, "on_bound", at);
  f.evaluations = integer(j, "evaluations", at, 0);
  const json& t = object_or_empty(j, "timing_s", at);
  const Where wt = at / "timing_s";
  f.timing_s = {number(t, "swarm", wt, k_nan), number(t, "local", wt, k_nan), number(t, "bending_check", wt, k_nan),
                number(t, "profile", wt, k_nan), number(t, "total", wt, k_nan)};
  if (const json* p = member(j, "identifiability")) f.identifiability = read_identifiability(*p, at / "identifiability");
  f.settings = read_settings(object_or_empty(j, "settings", at), at / "settings");
  if (const json* s = member(j, "swarm")) f.swarm = read_swarm(*s, at / "swarm");
  if (const json* g = member(j, "global")) f.global = read_global(*g, at / "global");
  if (const json* shape = member(j, "shape")) f.shape = read_shape(*shape, at / "shape");
  if (const json* tile = member(j, "tile")) f.tile = read_fitted_tile(*tile, at / "tile");
  if (const json* law = member(j, "homogenised_law")) f.measured = read_measured(j, *law, at);
  if (const json* l = member(j, "local")) {
    LocalRecord local{read_local_run(*l, at / "local"), {}};
    for_each_object(*l, "runs", at / "local",
                    [&local](const json& run, const Where& w) { local.runs.push_back(read_local_run(run, w)); });
    f.local = std::move(local);
  }
  return f;
}

YarnFitFile read_yarn_fit_file(const std::filesystem::path& path) {
  return yarn_fit_file_from_json(read_json_file(path), path.string());
}

}  // namespace yarnfit::results
