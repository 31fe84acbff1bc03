#include "results/shell_fit_file.hpp"

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
}  // namespace

namespace {

// The fields of one direction's curves, of one bending curve and of one direction's errors, each
// with the value a file without it reads as.
template <class Fields, class Curves>
void curves_fields(Fields& f, Curves& c) {
  f("direction", c.direction, std::string("?"));
  f("fitted_max_stretch", c.fitted_max_stretch, k_nan);
  f("measured_max_stretch", c.measured_max_stretch, k_nan);
  f("stretch", c.stretch, std::vector<double>());
  f("measured_force_N", c.measured_force_N, std::vector<double>());
  f("simulated_force_N", c.simulated_force_N, std::vector<double>());
  f("measured_compression", c.measured_compression, std::vector<double>());
  f("simulated_compression", c.simulated_compression, std::vector<double>());
}

template <class Fields, class Curve>
void bending_curve_fields(Fields& f, Curve& c) {
  f("direction", c.direction, std::string("?"));
  f("clamp_distance_m", c.clamp_distance_m, std::vector<double>());
  f("measured_aspect_ratio", c.measured_aspect_ratio, std::vector<double>());
  f("simulated_aspect_ratio", c.simulated_aspect_ratio, std::vector<double>());
}

template <class Fields, class Errors>
void shell_errors_fields(Fields& f, Errors& e) {
  f("stretch_force_pct", e.stretch_force_pct, k_nan);
  f("compression_pct", e.compression_pct, k_nan);
  f("bending_pct", e.bending_pct, k_nan);
}

}  // namespace

json curves_json(const ShellDirectionCurves& d) {
  return fields_json(d, [](auto& f, auto& c) { curves_fields(f, c); });
}

ShellDirectionCurves read_curves(const json& d, const Where& at) {
  return read_fields<ShellDirectionCurves>(d, at, [](auto& f, auto& c) { curves_fields(f, c); });
}

json bending_curve_json(const BendingCurve& c) {
  return fields_json(c, [](auto& f, auto& r) { bending_curve_fields(f, r); });
}

BendingCurve read_bending_curve(const json& c, const Where& w) {
  return read_fields<BendingCurve>(c, w, [](auto& f, auto& r) { bending_curve_fields(f, r); });
}

json direction_errors_json(const std::map<std::string, ShellDirectionErrors>& errors) {
  json j = json::object();
  for (const auto& [dir, e] : errors) j[dir] = fields_json(e, [](auto& f, auto& r) { shell_errors_fields(f, r); });
  return j;
}

ShellDirectionErrors read_shell_errors(const json& e, const Where& w) {
  return read_fields<ShellDirectionErrors>(e, w, [](auto& f, auto& r) { shell_errors_fields(f, r); });
}

namespace {

json bending_json(const BendingDetails& b) {
  json curves = json::array();
  for (const auto& c : b.curves) curves.push_back(bending_curve_json(c));
  return {{"converged", b.converged},
          {"message", b.message},
          {"iterations", b.iterations},
          {"simulations", b.simulations},
          {"timing_s", b.timing_s},
          {"at_bounds", b.at_bounds},
          {"curves", curves},
          {"not_identified", b.not_identified},
          {"fallback_starts", b.fallback_starts},
          {"errors_reason", string_or_null(b.errors_reason)}};
}

BendingDetails read_bending(const json& b, const Where& at) {
  expect_object(b, at);
  BendingDetails out;
  out.converged = boolean(b, "converged", at, false);
  out.message = string(b, "message", at);
  out.iterations = integer(b, "iterations", at, 0);
  out.simulations = integer(b, "simulations", at, 0);
  out.timing_s = number(b, "timing_s", at, k_nan);
  out.at_bounds = strings(b, "at_bounds", at);
  if (const json* curves = member(b, "curves")) {
    if (!curves->is_array()) (at / "curves").bad("an array");
    for (std::size_t i = 0; i < curves->size(); ++i) {
      out.curves.push_back(read_bending_curve((*curves)[i], (at / "curves")[i]));
    }
  }
  out.not_identified = strings(b, "not_identified", at);
  out.fallback_starts = strings(b, "fallback_starts", at);
  out.errors_reason = string(b, "errors_reason", at);
  return out;
}

std::map<std::string, ShellDirectionErrors> read_direction_errors(const json& j, const Where& at) {
  std::map<std::string, ShellDirectionErrors> out;
  const json* v = member(j, "errors_by_direction");
  if (!v) at.bad("errors_by_direction (schema version 2 and later)");
  expect_object(*v, at / "errors_by_direction");
  for (const auto& [dir, e] : v->items()) {
    out[dir] = read_shell_errors(e, at / "errors_by_direction" / dir);
  }
  return out;
}

}  // namespace

ShellDirectionErrors ShellFitFile::direction_errors(const std::string& direction) const {
  const auto it = errors_by_direction.find(direction);
  return it == errors_by_direction.end() ? ShellDirectionErrors{k_nan, k_nan, k_nan} : it->second;
}

std::map<std::string, ShellDirectionErrors> shell_direction_errors(const std::vector<ShellDirectionCurves>& directions,
                                                                  const std::optional<BendingDetails>& bending) {
  std::map<std::string, ShellDirectionErrors> out;
  const auto entry = [&out](const std::string& dir) -> ShellDirectionErrors& {
    return out.try_emplace(dir, ShellDirectionErrors{k_nan, k_nan, k_nan}).first->second;
  };
  for (const auto& d : directions) {
    ShellDirectionErrors& e = entry(d.direction);
    e.stretch_force_pct = shell_error_pct(d.measured_force_N, d.simulated_force_N);
    e.compression_pct = shell_error_pct(d.measured_compression, d.simulated_compression);
  }
  if (bending)
    for (const auto& c : bending->curves)
      entry(c.direction).bending_pct = shell_error_pct(c.measured_aspect_ratio, c.simulated_aspect_ratio);
  return out;
}

std::map<std::string, double> named_errors(const ShellErrors& e) {
  return {{"stretch_force_pct", e.stretch_force_pct}, {"compression_pct", e.compression_pct}, {"bending_pct", e.bending_pct}};
}

json params_json(const std::map<std::string, std::optional<double>>& params) {
  json j = json::object();
  for (const auto& [name, v] : params) j[name] = v ? json(*v) : json(nullptr);
  return j;
}

namespace {

json fab_json(const FabFitDetails& fab) {
  json bends = json::array(), tests = json::array();
  for (const auto& b : fab.bends)
    bends.push_back({{"direction", b.direction},
                     {"ktheta", b.ktheta},
                     {"ktheta_range", {b.ktheta_low, b.ktheta_high}},
                     {"force_pct", pct_json(b.force_pct)},
                     {"converged", b.converged},
                     {"on_bound", b.on_bound},
                     {"evaluations", b.evaluations},
                     {"timing_s", b.timing_s},
                     {"message", b.message}});
  for (const auto& t : fab.tests)
    tests.push_back({{"direction", t.direction},
                     {"test", t.test},
                     {"held_out", t.held_out},
                     {"samples", t.samples},
                     {"force_pct", pct_json(t.force_pct)},
                     {"first_cycles_force_pct", pct_json(t.first_cycles_force_pct)},
                     {"mean_abs_error_N", pct_json(t.mean_abs_error_N)},
                     {"offset_N", t.offset_N},
                     {"spread_pct", pct_json(t.spread_pct)},
                     {"hysteresis_pct", pct_json(t.hysteresis_pct)},
                     {"converged", t.converged},
                     {"message", t.message}});
  return {{"held_out", fab.held_out}, {"bends", bends}, {"tests", tests}, {"timing_s", fab.timing_s}};
}

// The held-out tests' errors by direction and test, named as errors_by_direction names them.
json held_out_json(const FabFitDetails& fab) {
  json j = json::object();
  for (const auto& t : fab.tests)
    if (t.held_out)
      j[t.direction][t.test] = {{t.test[0] == 'S' ? "stretch_force_pct" : "bending_force_pct", pct_json(t.force_pct)}};
  return j;
}

FabFitDetails read_fab(const json& j, const Where& at) {
  expect_object(j, at);
  FabFitDetails fab;
  fab.held_out = strings(j, "held_out", at);
  fab.timing_s = number(j, "timing_s", at, k_nan);
  if (const json* bends = member(j, "bends")) {
    if (!bends->is_array()) (at / "bends").bad("an array");
    for (std::size_t i = 0; i < bends->size(); ++i) {
      const json& b = (*bends)[i];
      const Where w = (at / "bends")[i];
      expect_object(b, w);
      const std::vector<double> range = numbers(b, "ktheta_range", w);
      fab.bends.push_back({string(b, "direction", w, "?"), number(b, "ktheta", w, k_nan),
                           range.size() == 2 ? range[0] : k_nan, range.size() == 2 ? range[1] : k_nan,
                           number(b, "force_pct", w, k_nan),
                           boolean(b, "converged", w, false), boolean(b, "on_bound", w, false),
                           integer(b, "evaluations", w, 0), number(b, "timing_s", w, k_nan), string(b, "message", w)});
    }
  }
  if (const json* tests = member(j, "tests")) {
    if (!tests->is_array()) (at / "tests").bad("an array");
    for (std::size_t i = 0; i < tests->size(); ++i) {
      const json& t = (*tests)[i];
      const Where w = (at / "tests")[i];
      expect_object(t, w);
      fab.tests.push_back({string(t, "direction", w, "?"), string(t, "test", w, "?"), boolean(t, "held_out", w, false),
                           integer(t, "samples", w, 0), number(t, "force_pct", w, k_nan),
                           number(t, "first_cycles_force_pct", w, k_nan), number(t, "mean_abs_error_N", w, k_nan),
                           number(t, "offset_N", w, k_nan), number(t, "spread_pct", w, k_nan),
                           number(t, "hysteresis_pct", w, k_nan), boolean(t, "converged", w, false),
                           string(t, "message", w)});
    }
  }
  return fab;
}

}  // namespace

json to_json(const ShellFitFile& f) {
  json errors = json::object();
  for (const auto& [name, v] : named_errors(f.errors)) errors[name] = pct_json(v);
  json starts = json::array();
  for (const auto& s : f.starts)
    starts.push_back({{"name", s.name},
                      {"params", s.params},
                      {"usable", s.usable},
                      {"cost", pct_json(s.cost)},
                      {"iterations", s.iterations}});
  json thesis = nullptr;
  if (f.thesis_model_fit)
    thesis = {{"params", f.thesis_model_fit->params},
              {"errors",
               {{"stretch_force_pct", pct_json(f.thesis_model_fit->stretch_force_pct)},
                {"compression_pct", pct_json(f.thesis_model_fit->compression_pct)}}}};
  json directions = json::array();
  for (const auto& d : f.directions) directions.push_back(curves_json(d));
  json j = {{"schema_version", k_shell_fit_schema_version},
            {"fabric", f.fabric},
            {"family", f.family},
            {"model", f.model},
            {"params", params_json(f.params)},
            {"start", f.start},
            {"thesis_model_fit", thesis},
            {"hit_iteration_cap", f.hit_iteration_cap},
            {"starts", starts},
            {"chosen_start", f.chosen_start},
            {"errors", errors},
            {"errors_by_direction", direction_errors_json(f.errors_by_direction)},
            {"errors_reason", string_or_null(f.errors_reason)},
            {"identified", f.identified},
            {"not_identified", f.not_identified},
            {"at_bounds", f.at_bounds},
            {"bounds", bounds_json(f.bounds)},
            {"weakly_identified", f.weakly_identified},
            {"sensitivity_pct_per_pct_noise", number_map_json(f.sensitivity_pct_per_pct_noise)},
            {"converged", f.converged},
            {"message", f.message},
            {"iterations", f.iterations},
            {"restarts", f.restarts},
            {"simulations", f.simulations},
            {"directions", directions},
            {"timing_s", f.timing_s},
            {"effects", f.effects}};
  if (f.inplane)
    j["inplane"] = {{"timing_s", f.inplane->timing_s},
                    {"not_identified", f.inplane->not_identified},
                    {"at_bounds", f.inplane->at_bounds},
                    {"compression_measured", f.inplane->compression_measured},
                    {"errors_reason", string_or_null(f.inplane->errors_reason)}};
  if (f.bending) j["bending"] = bending_json(*f.bending);
  if (f.fab) {
    j["fab"] = fab_json(*f.fab);
    j["held_out_errors_by_direction"] = held_out_json(*f.fab);
  }
  return j;
}

ShellFitFile shell_fit_file_from_json(const json& j, const std::string& source) {
  const Where at(source);
  ShellFitFile f = open_result<ShellFitFile>(j, at, k_shell_fit_schema_version);
  f.fabric = string(j, "fabric", at);
  f.family = string(j, "family", at);
  f.model = string(j, "model", at, "thesis");  // files from before the choice are eq. 6.1
  const json* params = member(j, "params");
  if (!params) at.bad("params (the fitted parameters)");
  expect_object(*params, at / "params");
  for (const auto& [name, v] : params->items()) f.params[name] = optional_number(*params, name.c_str(), at / "params");
  f.start = number_map(j, "start", at);
  if (const json* t = member(j, "thesis_model_fit"); t && !t->is_null()) {
    const Where w = at / "thesis_model_fit";
    expect_object(*t, w);
    ThesisModelFit thesis;
    thesis.params = number_map(*t, "params", w);
    const json* e = member(*t, "errors");
    const json none = json::object();
    thesis.stretch_force_pct = number(e ? *e : none, "stretch_force_pct", w / "errors", k_nan);
    thesis.compression_pct = number(e ? *e : none, "compression_pct", w / "errors", k_nan);
    f.thesis_model_fit = thesis;
  }
  f.hit_iteration_cap = boolean(j, "hit_iteration_cap", at, false);
  if (const json* starts = member(j, "starts")) {
    if (!starts->is_array()) (at / "starts").bad("an array");
    for (std::size_t i = 0; i < starts->size(); ++i) {
      const json& s = (*starts)[i];
      const Where w = (at / "starts")[i];
      expect_object(s, w);
      f.starts.push_back({string(s, "name", w), number_map(s, "params", w), boolean(s, "usable", w, false),
                          number(s, "cost", w, k_nan), integer(s, "iterations", w, 0)});
    }
  }
  f.chosen_start = integer(j, "chosen_start", at, -1);
  const json none = json::object();
  const json* errors = member(j, "errors");
  if (errors) expect_object(*errors, at / "errors");
  const json& e = errors ? *errors : none;
  f.errors = {number(e, "stretch_force_pct", at / "errors", k_nan), number(e, "compression_pct", at / "errors", k_nan),
              number(e, "bending_pct", at / "errors", k_nan)};
  f.errors_reason = string(j, "errors_reason", at);
  if (const json* in = member(j, "inplane")) {
    const Where w = at / "inplane";
    expect_object(*in, w);
    f.inplane = InplaneDetails{number(*in, "timing_s", w, k_nan), strings(*in, "not_identified", w),
                               strings(*in, "at_bounds", w), boolean(*in, "compression_measured", w, true),
                               string(*in, "errors_reason", w)};
  }
  f.identified = strings(j, "identified", at);
  f.not_identified = strings(j, "not_identified", at);
  f.at_bounds = strings(j, "at_bounds", at);
  f.bounds = read_bounds(j, at);
  f.weakly_identified = strings(j, "weakly_identified", at);
  f.sensitivity_pct_per_pct_noise = number_map(j, "sensitivity_pct_per_pct_noise", at);
  f.converged = boolean(j, "converged", at, false);
  f.message = string(j, "message", at);
  f.iterations = integer(j, "iterations", at, 0);
  f.restarts = integer(j, "restarts", at, 0);
  f.simulations = integer(j, "simulations", at, 0);
  if (const json* dirs = member(j, "directions")) {
    if (!dirs->is_array()) (at / "directions").bad("an array");
    for (std::size_t i = 0; i < dirs->size(); ++i) f.directions.push_back(read_curves((*dirs)[i], (at / "directions")[i]));
  }
  f.timing_s = number(j, "timing_s", at, k_nan);
  f.effects = string_lists(j, "effects", at);
  if (const json* b = member(j, "bending")) f.bending = read_bending(*b, at / "bending");
  if (const json* fab = member(j, "fab")) f.fab = read_fab(*fab, at / "fab");
  // Version 1 did not store the per-direction errors: its readers computed them from the curves.
  f.errors_by_direction =
      f.schema_version >= 2 ? read_direction_errors(j, at) : shell_direction_errors(f.directions, f.bending);
  return f;
}

ShellFitFile read_shell_fit_file(const std::filesystem::path& path) {
  return shell_fit_file_from_json(read_json_file(path), path.string());
}

}  // namespace yarnfit::results
