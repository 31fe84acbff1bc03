#include "calibration/fit/fit_checkpoint.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "fabrics_db/text_util.hpp"
#include "swarm/json_numbers.hpp"

namespace yarnfit::calibration {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "yarnfit fit checkpoint";
constexpr int kVersion = 1;

using swarm::json_columns;
using swarm::json_number;
using swarm::json_vector;

// A number as json_number wrote it; anything else is a damaged checkpoint, never a NaN.
double real(const json& j) {
  if (const auto v = swarm::json_real(j)) return *v;
  throw std::runtime_error("expected a number, got " + j.dump());
}

Eigen::VectorXd vector_of(const json& j) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t i = 0; i < j.size(); ++i) v[static_cast<Eigen::Index>(i)] = real(j[i]);
  return v;
}

Eigen::MatrixXd matrix_of(const json& j) {
  if (j.empty()) return {};
  Eigen::MatrixXd m(static_cast<Eigen::Index>(j[0].size()), static_cast<Eigen::Index>(j.size()));
  for (std::size_t c = 0; c < j.size(); ++c) m.col(static_cast<Eigen::Index>(c)) = vector_of(j[c]);
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
  r.round = j.at("round").get<int>();
  r.g_start = real(j.at("g_start"));
  r.g_end = real(j.at("g_end"));
  r.g_true = real(j.at("g_true"));
  r.accepted = j.at("accepted").get<bool>();
  r.move = real(j.at("move"));
  r.evaluations = j.at("evaluations").get<int>();
  r.iterations = j.at("iterations").get<int>();
  r.termination = j.at("termination").get<std::string>();
  r.failed = j.at("failed").get<bool>();
  r.seconds = j.at("seconds").get<double>();
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
  s.ok = j.at("ok").get<bool>();
  s.message = j.at("message").get<std::string>();
  s.best_point = vector_of(j.at("best_point"));
  s.best_value = real(j.at("best_value"));
  s.start_value = real(j.at("start_value"));
  for (const auto& r : j.at("rounds")) s.rounds.push_back(round_of(r));
  s.converged = j.at("converged").get<bool>();
  s.last_move = real(j.at("last_move"));
  s.evaluations = j.at("evaluations").get<int>();
  s.failed_evaluations = j.at("failed_evaluations").get<int>();
  s.fell_back = j.at("fell_back").get<bool>();
  s.fallback_reason = j.at("fallback_reason").get<std::string>();
  s.fallback.message = j.at("fallback_report").get<std::string>();
  s.residuals = vector_of(j.at("residuals"));
  s.jacobian_log = matrix_of(j.at("jacobian_log"));
  s.seconds = j.at("seconds").get<double>();
  return s;
}

}  // namespace

FitCheckpoint read_fit_checkpoint(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("fit checkpoint " + file.string() + ": cannot be read");
  FitCheckpoint out;
  try {
    const json j = json::parse(in);
    if (j.value("format", std::string()) != kFormat || j.value("version", 0) != kVersion)
      throw std::runtime_error("not a version " + std::to_string(kVersion) + " yarnfit fit checkpoint");
    if (j.contains("rescored")) {
      std::vector<GlobalCandidate> c;
      for (const auto& e : j.at("rescored")) c.push_back({vector_of(e.at("point")), real(e.at("value"))});
      out.rescored = std::move(c);
    }
    for (const auto& e : j.at("local")) {
      if (e.is_null()) out.local.emplace_back();
      else out.local.emplace_back(run_of(e));
    }
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("fit checkpoint " + file.string() + ": " + e.what());
  } catch (const json::exception& e) {
    throw std::runtime_error("fit checkpoint " + file.string() + ": " + e.what());
  }
  return out;
}

void write_fit_checkpoint(const std::filesystem::path& file, const FitCheckpoint& checkpoint) {
  json j{{"format", kFormat}, {"version", kVersion}};
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

}  // namespace yarnfit::calibration
