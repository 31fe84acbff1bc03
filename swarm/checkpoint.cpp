// Swarm checkpoints as JSON. Doubles are written with 17 significant digits, which
// round-trips every finite double exactly; ±inf and NaN, which JSON has no numbers for, are
// written as the strings "inf", "-inf" and "nan".

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "swarm/checkpoint_json.hpp"
#include "numerics/util/error.hpp"
#include "swarm/swarm_state.hpp"

#include "numerics/util/whole_file.hpp"

namespace yarnfit::swarm::detail {

namespace {

using nlohmann::json;

constexpr CheckpointKind k_swarm_checkpoint{"checkpoint", "yarnfit swarm checkpoint", 1};

using swarm::json_columns;
using swarm::json_number;
using swarm::json_vector;

// Reads fields of one checkpoint file; every error names the file and the field.
class Reader {
 public:
  explicit Reader(std::filesystem::path path) : m_path(std::move(path)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw Error(ErrorCategory::input, "checkpoint " + m_path.string() + ": " + field + ": " + message);
  }

  const json& at(const json& parent, const std::string& key, const std::string& field) const {
    if (!parent.is_object() || !parent.contains(key)) fail(field, "missing");
    return parent.at(key);
  }

  double real(const json& j, const std::string& field) const {
    if (const auto v = json_real(j)) return *v;
    fail(field, "expected a number, got " + j.dump());
  }
  double real(const json& parent, const std::string& key, const std::string& prefix) const {
    return real(at(parent, key, prefix + key), prefix + key);
  }

  template <typename Int>
  Int integer(const json& parent, const std::string& key, const std::string& prefix) const {
    const json& j = at(parent, key, prefix + key);
    if (!j.is_number_integer()) fail(prefix + key, "expected an integer, got " + j.dump());
    return j.get<Int>();
  }

  std::string text(const json& parent, const std::string& key, const std::string& prefix) const {
    const json& j = at(parent, key, prefix + key);
    if (!j.is_string()) fail(prefix + key, "expected a string, got " + j.dump());
    return j.get<std::string>();
  }

  bool boolean(const json& parent, const std::string& key, const std::string& prefix) const {
    const json& j = at(parent, key, prefix + key);
    if (!j.is_boolean()) fail(prefix + key, "expected true or false, got " + j.dump());
    return j.get<bool>();
  }

  const json& array(const json& parent, const std::string& key, const std::string& field) const {
    const json& j = at(parent, key, field);
    if (!j.is_array()) fail(field, "expected an array");
    return j;
  }

  Eigen::VectorXd vector(const json& j, Eigen::Index size, const std::string& field) const {
    if (!j.is_array()) fail(field, "expected an array");
    if (size >= 0 && static_cast<Eigen::Index>(j.size()) != size) {
      fail(field, "expected " + std::to_string(size) + " entries, found " + std::to_string(j.size()));
    }
    Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
    for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = real(j[i], field);
    return v;
  }

  Eigen::MatrixXd columns(const json& parent, const std::string& key, Eigen::Index rows, Eigen::Index cols) const {
    const json& j = array(parent, key, key);
    if (static_cast<Eigen::Index>(j.size()) != cols) {
      fail(key, "expected " + std::to_string(cols) + " particles, found " + std::to_string(j.size()));
    }
    Eigen::MatrixXd m(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c) {
      m.col(c) = vector(j[static_cast<std::size_t>(c)], rows, key + "[" + std::to_string(c) + "]");
    }
    return m;
  }

 private:
  std::filesystem::path m_path;
};

json space_json(const ParameterSpace& space) {
  json out = json::array();
  for (const auto& p : space.parameters()) {
    out.push_back({{"name", p.name}, {"lower", p.lower}, {"upper", p.upper}, {"log_space", p.log_space}});
  }
  return out;
}

void check_space(const Reader& r, const json& j, const ParameterSpace& space) {
  if (!j.is_array()) r.fail("space", "expected an array");
  if (static_cast<int>(j.size()) != space.dimension()) {
    r.fail("space", "the run had " + std::to_string(j.size()) + " parameters, this one has " +
                        std::to_string(space.dimension()));
  }
  for (int i = 0; i < space.dimension(); ++i) {
    const json& p = j[static_cast<std::size_t>(i)];
    const std::string prefix = "space[" + std::to_string(i) + "].";
    const Parameter& want = space.parameter(i);
    const std::string name = r.text(p, "name", prefix);
    const double lower = r.real(p, "lower", prefix);
    const double upper = r.real(p, "upper", prefix);
    const bool log_space = r.boolean(p, "log_space", prefix);
    auto differ = [&](const std::string& field, const std::string& theirs, const std::string& ours) {
      r.fail(prefix + field, "the run had " + theirs + " for " + space.label(i) + ", the caller gives " + ours);
    };
    if (name != want.name) differ("name", "'" + name + "'", "'" + want.name + "'");
    if (lower != want.lower) differ("lower", json(lower).dump(), json(want.lower).dump());
    if (upper != want.upper) differ("upper", json(upper).dump(), json(want.upper).dump());
    if (log_space != want.log_space) differ("log_space", json(log_space).dump(), json(want.log_space).dump());
  }
}

json settings_json(const SwarmSettings& s) {
  return {{"particles", s.particles},
          {"iterations", s.iterations},
          {"inertia_start", s.inertia_start},
          {"inertia_end", s.inertia_end},
          {"cognitive", s.cognitive},
          {"social", s.social},
          {"max_velocity", s.max_velocity},
          {"repulsion_radius", s.repulsion_radius},
          {"repulsion_strength", s.repulsion_strength},
          {"seed", s.seed}};
}

SwarmSettings read_settings(const Reader& r, const json& j) {
  const std::string p = "settings.";
  SwarmSettings s;
  s.particles = r.integer<int>(j, "particles", p);
  s.iterations = r.integer<int>(j, "iterations", p);
  s.inertia_start = r.real(j, "inertia_start", p);
  s.inertia_end = r.real(j, "inertia_end", p);
  s.cognitive = r.real(j, "cognitive", p);
  s.social = r.real(j, "social", p);
  s.max_velocity = r.real(j, "max_velocity", p);
  s.repulsion_radius = r.real(j, "repulsion_radius", p);
  s.repulsion_strength = r.real(j, "repulsion_strength", p);
  s.seed = r.integer<std::uint64_t>(j, "seed", p);
  if (const numerics::Problems problems = s.problems(); !problems.empty()) r.fail("settings", problems.one_line());
  return s;
}

json history_json(const std::vector<IterationRecord>& history) {
  json out = json::array();
  for (const auto& h : history) {
    out.push_back({{"iteration", h.iteration},
                   {"best_value", json_number(h.best_value)},
                   {"iteration_best", json_number(h.iteration_best)},
                   {"mean_value", json_number(h.mean_value)},
                   {"failed", h.failed},
                   {"neighbour_distance", json_number(h.neighbour_distance)},
                   {"inertia", json_number(h.inertia)},
                   {"seconds", json_number(h.seconds)}});
  }
  return out;
}

std::vector<IterationRecord> read_history(const Reader& r, const json& j) {
  std::vector<IterationRecord> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = "summary.history[" + std::to_string(i) + "].";
    IterationRecord h;
    h.iteration = r.integer<int>(j[i], "iteration", p);
    h.best_value = r.real(j[i], "best_value", p);
    h.iteration_best = r.real(j[i], "iteration_best", p);
    h.mean_value = r.real(j[i], "mean_value", p);
    h.failed = r.integer<int>(j[i], "failed", p);
    h.neighbour_distance = r.real(j[i], "neighbour_distance", p);
    h.inertia = r.real(j[i], "inertia", p);
    h.seconds = r.real(j[i], "seconds", p);
    out.push_back(h);
  }
  return out;
}

json failures_json(const std::vector<FailedEvaluation>& failures) {
  json out = json::array();
  for (const auto& f : failures) {
    out.push_back({{"evaluation", f.evaluation},
                   {"iteration", f.iteration},
                   {"particle", f.particle},
                   {"x", json_vector(f.x)},
                   {"message", f.message}});
  }
  return out;
}

std::vector<FailedEvaluation> read_failures(const Reader& r, const json& j, int dimension) {
  std::vector<FailedEvaluation> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = "summary.failures[" + std::to_string(i) + "].";
    FailedEvaluation f;
    f.evaluation = r.integer<int>(j[i], "evaluation", p);
    f.iteration = r.integer<int>(j[i], "iteration", p);
    f.particle = r.integer<int>(j[i], "particle", p);
    f.x = r.vector(r.at(j[i], "x", p + "x"), dimension, p + "x");
    f.message = r.text(j[i], "message", p);
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const ParameterSpace& space, const SwarmState& state) {
  const SwarmSummary& s = state.summary;
  json doc = checkpoint_preamble(k_swarm_checkpoint);
  doc.update({
      {"space", space_json(space)},
      {"settings", settings_json(state.settings)},
      {"iterations_done", state.iterations_done},
      {"random_state", state.random_state},
      {"position", json_columns(state.position)},
      {"velocity", json_columns(state.velocity)},
      {"best_position", json_columns(state.best_position)},
      {"best_value", json_vector(state.best_value)},
      {"global_best", json_vector(state.global_best)},
      {"summary",
       {{"best_value", json_number(s.best_value)},
        {"best_iteration", s.best_iteration},
        {"best_particle", s.best_particle},
        {"evaluations", s.evaluations},
        {"failed", s.failed},
        {"seconds", json_number(s.seconds)},
        {"history", history_json(s.history)},
        {"failures", failures_json(s.failures)}}},
  });
  try {
    numerics::write_file_whole(path, doc.dump(1) + "\n");
  } catch (const Error& e) {
    throw with_context("checkpoint " + path.string() + ": ", e);
  }
}

SwarmState read_checkpoint(const std::filesystem::path& path, const ParameterSpace& space) {
  const Reader r(path);
  const json doc = read_checkpoint_json(path, k_swarm_checkpoint);
  check_space(r, r.at(doc, "space", "space"), space);

  SwarmState st;
  st.settings = read_settings(r, r.at(doc, "settings", "settings"));
  const Eigen::Index d = space.dimension();
  const Eigen::Index n = st.settings.particles;
  st.iterations_done = r.integer<int>(doc, "iterations_done", "");
  if (st.iterations_done < 1 || st.iterations_done > st.settings.iterations) {
    r.fail("iterations_done", "must be in [1, settings.iterations]");
  }
  st.random_state = r.text(doc, "random_state", "");
  st.position = r.columns(doc, "position", d, n);
  st.velocity = r.columns(doc, "velocity", d, n);
  st.best_position = r.columns(doc, "best_position", d, n);
  st.best_value = r.vector(r.at(doc, "best_value", "best_value"), n, "best_value");
  st.global_best = r.vector(r.at(doc, "global_best", "global_best"), d, "global_best");

  const json& sj = r.at(doc, "summary", "summary");
  SwarmSummary& s = st.summary;
  s.settings = st.settings;
  s.best_value = r.real(sj, "best_value", "summary.");
  s.best_iteration = r.integer<int>(sj, "best_iteration", "summary.");
  s.best_particle = r.integer<int>(sj, "best_particle", "summary.");
  s.evaluations = r.integer<int>(sj, "evaluations", "summary.");
  s.failed = r.integer<int>(sj, "failed", "summary.");
  s.seconds = r.real(sj, "seconds", "summary.");
  s.history = read_history(r, r.array(sj, "history", "summary.history"));
  if (static_cast<int>(s.history.size()) != st.iterations_done) {
    r.fail("summary.history", "expected one record per iteration done (" + std::to_string(st.iterations_done) + ")");
  }
  s.failures = read_failures(r, r.array(sj, "failures", "summary.failures"), space.dimension());
  if (s.usable()) s.best_point = space.from_unit(st.global_best);
  return st;
}

}  // namespace yarnfit::swarm::detail
