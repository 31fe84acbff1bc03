#include "yarn_fit/fit/fit_checkpoint.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"
#include "swarm/checkpoint_json.hpp"

namespace yarnfit::yarn {

namespace {

using nlohmann::json;

constexpr swarm::CheckpointKind k_fit_checkpoint{"fit checkpoint", "yarnfit fit checkpoint", 1};

using swarm::json_columns;
using swarm::json_number;
using swarm::json_vector;

// Every reader below names the field it failed on ("local[0].rounds[2].g_end: expected a
// number, got \"x\""): a BadField carries the path so far, and `in` adds one step of the path
// in front of whatever its body throws.
struct BadField {
  std::string path;    // "rounds[2].g_end", "[3]"
  std::string reason;  // "expected a number, got \"x\""
};

std::string joined(const std::string& step, const std::string& rest) {
  if (rest.empty()) return step;
  return step + (rest.front() == '[' ? "" : ".") + rest;
}

template <class F>
auto in(const std::string& step, F&& body) -> decltype(body()) {
  try {
    return body();
  } catch (const BadField& e) {
    throw BadField{joined(step, e.path), e.reason};
  } catch (const json::exception& e) {
    throw BadField{step, e.what()};
  } catch (const std::runtime_error& e) {
    throw BadField{step, e.what()};
  }
}

std::string indexed(const char* key, std::size_t i) { return std::string(key) + "[" + std::to_string(i) + "]"; }

const json& field(const json& j, const char* key) {
  if (!j.is_object()) throw BadField{"", "expected an object, got " + j.dump()};
  const auto it = j.find(key);
  if (it == j.end()) throw BadField{key, "missing"};
  return *it;
}

template <class T>
T get(const json& j, const char* key) {
  const json& v = field(j, key);
  try {
    return v.get<T>();
  } catch (const json::exception&) {
    throw BadField{key, std::string("expected ") +
                            (std::is_same_v<T, bool>          ? "true or false"
                             : std::is_same_v<T, std::string> ? "a string"
                                                              : "a number") +
                            ", got " + v.dump()};
  }
}

// A number as json_number wrote it; anything else is a damaged checkpoint, never a NaN.
double real(const json& j) {
  if (const auto v = swarm::json_real(j)) return *v;
  throw Error(ErrorCategory::input, "expected a number, got " + j.dump());
}

Eigen::VectorXd vector_of(const json& j) {
  if (!j.is_array()) throw Error(ErrorCategory::input, "expected an array of numbers, got " + j.dump());
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = in("[" + std::to_string(i) + "]", [&] { return real(j[i]); });
  return v;
}

double real_at(const json& j, const char* key) {
  const json& v = field(j, key);
  return in(key, [&] { return real(v); });
}
Eigen::VectorXd vector_at(const json& j, const char* key) {
  const json& v = field(j, key);
  return in(key, [&] { return vector_of(v); });
}

Eigen::MatrixXd matrix_of(const json& j) {
  if (!j.is_array()) throw Error(ErrorCategory::input, "expected an array of columns, got " + j.dump());
  if (j.empty()) return {};
  if (!j[0].is_array()) throw BadField{"[0]", "expected an array of numbers, got " + j[0].dump()};
  Eigen::MatrixXd m(static_cast<Eigen::Index>(j[0].size()), static_cast<Eigen::Index>(j.size()));
  for (std::size_t c = 0; c < j.size(); ++c) {
    const Eigen::VectorXd column = in("[" + std::to_string(c) + "]", [&] { return vector_of(j[c]); });
    if (column.size() != m.rows())
      throw BadField{"[" + std::to_string(c) + "]", "a column of " + std::to_string(column.size()) +
                                                        " numbers among columns of " + std::to_string(m.rows())};
    m.col(static_cast<Eigen::Index>(c)) = column;
  }
  return m;
}

json round_json(const AlternationRound& r) {
  return {{"round", r.round},       {"g_start", json_number(r.g_start)}, {"g_end", json_number(r.g_end)},
          {"g_true", json_number(r.g_true)}, {"accepted", r.accepted},   {"move", json_number(r.move)},
          {"evaluations", r.evaluations}, {"iterations", r.iterations}, {"termination", r.termination},
          {"failed", r.failed},     {"seconds", r.seconds}, {"rest_derivative_measured", r.rest_derivative_measured}};
}

AlternationRound round_of(const json& j) {
  AlternationRound r;
  r.round = get<int>(j, "round");
  r.g_start = real_at(j, "g_start");
  r.g_end = real_at(j, "g_end");
  r.g_true = real_at(j, "g_true");
  r.accepted = get<bool>(j, "accepted");
  r.move = real_at(j, "move");
  r.evaluations = get<int>(j, "evaluations");
  r.iterations = get<int>(j, "iterations");
  r.termination = get<std::string>(j, "termination");
  r.failed = get<bool>(j, "failed");
  r.seconds = get<double>(j, "seconds");
  r.rest_derivative_measured = j.value("rest_derivative_measured", false);  // absent before issue 49
  return r;
}

json run_json(const AlternationSummary& s) {
  json rounds = json::array();
  for (const auto& r : s.rounds) rounds.push_back(round_json(r));
  return {{"ok", s.ok},
          {"message", s.message},
          {"best_point", json_vector(s.best_point)},
          {"best_value", json_number(s.best_value)},
          {"start_value", json_number(s.start_value)},
          {"rounds", rounds},
          {"converged", s.converged},
          {"last_move", json_number(s.last_move)},
          {"evaluations", s.evaluations},
          {"failed_evaluations", s.failed_evaluations},
          {"fell_back", s.fell_back},
          {"fallback_reason", s.fallback_reason},
          {"fallback_report", s.fell_back ? s.fallback.brief_report() : std::string()},
          {"residuals", json_vector(s.residuals)},
          {"jacobian_log", json_columns(s.jacobian_log)},
          {"seconds", s.seconds}};
}

AlternationSummary run_of(const json& j) {
  AlternationSummary s;
  s.ok = get<bool>(j, "ok");
  s.message = get<std::string>(j, "message");
  s.best_point = vector_at(j, "best_point");
  s.best_value = real_at(j, "best_value");
  s.start_value = real_at(j, "start_value");
  const json& rounds = field(j, "rounds");
  if (!rounds.is_array()) throw BadField{"rounds", "expected an array, got " + rounds.dump()};
  for (std::size_t i = 0; i < rounds.size(); ++i)
    s.rounds.push_back(in(indexed("rounds", i), [&] { return round_of(rounds[i]); }));
  s.converged = get<bool>(j, "converged");
  s.last_move = real_at(j, "last_move");
  s.evaluations = get<int>(j, "evaluations");
  s.failed_evaluations = get<int>(j, "failed_evaluations");
  s.fell_back = get<bool>(j, "fell_back");
  s.fallback_reason = get<std::string>(j, "fallback_reason");
  s.fallback.message = get<std::string>(j, "fallback_report");
  s.residuals = vector_at(j, "residuals");
  const json& jacobian_log = field(j, "jacobian_log");
  s.jacobian_log = in("jacobian_log", [&] { return matrix_of(jacobian_log); });
  s.seconds = get<double>(j, "seconds");
  return s;
}

}  // namespace

FitCheckpoint read_fit_checkpoint(const std::filesystem::path& file) {
  const json j = swarm::read_checkpoint_json(file, k_fit_checkpoint);
  FitCheckpoint out;
  try {
    if (j.contains("rescored")) {
      const json& rescored = j["rescored"];
      if (!rescored.is_array()) throw BadField{"rescored", "expected an array, got " + rescored.dump()};
      std::vector<GlobalCandidate> c;
      for (std::size_t i = 0; i < rescored.size(); ++i)
        c.push_back(in(indexed("rescored", i), [&] {
          return GlobalCandidate{vector_at(rescored[i], "point"), real_at(rescored[i], "value")};
        }));
      out.rescored = std::move(c);
    }
    const json& local = field(j, "local");
    if (!local.is_array()) throw BadField{"local", "expected an array, got " + local.dump()};
    for (std::size_t i = 0; i < local.size(); ++i) {
      if (local[i].is_null()) out.local.emplace_back();
      else out.local.emplace_back(in(indexed("local", i), [&] { return run_of(local[i]); }));
    }
  } catch (const BadField& e) {
    throw Error(ErrorCategory::input, "fit checkpoint " + file.string() + ": " + e.path + ": " + e.reason);
  } catch (const std::runtime_error& e) {
    throw Error(ErrorCategory::input, "fit checkpoint " + file.string() + ": " + e.what());
  } catch (const json::exception& e) {
    throw Error(ErrorCategory::input, "fit checkpoint " + file.string() + ": " + e.what());
  }
  return out;
}

void write_fit_checkpoint(const std::filesystem::path& file, const FitCheckpoint& checkpoint) {
  json j = swarm::checkpoint_preamble(k_fit_checkpoint);
  if (checkpoint.rescored) {
    json c = json::array();
    for (const auto& g : *checkpoint.rescored) c.push_back({{"point", json_vector(g.point)}, {"value", json_number(g.value)}});
    j["rescored"] = c;
  }
  json local = json::array();
  for (const auto& run : checkpoint.local) local.push_back(run ? run_json(*run) : json());
  j["local"] = local;
  db::write_text_file_atomically(file, j.dump(1) + "\n");
}

void remove_fit_checkpoint(const std::filesystem::path& file) {
  std::filesystem::remove(file);
  for (const char* stage : {"contact", "all", "swarm"}) std::filesystem::remove(file.string() + "." + stage);
}

}  // namespace yarnfit::yarn
