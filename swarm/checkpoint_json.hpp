#pragma once
// What the swarm's and the fit's checkpoints share: the preamble each opens with and its check
// on reading, and doubles and Eigen vectors as JSON: finite values as numbers (17 significant
// digits, which round-trips every finite double), ±inf and NaN, which JSON has no numbers for,
// as the strings "inf", "-inf" and "nan"; and read back.

#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <nlohmann/json.hpp>

namespace yarnfit::swarm {

// A kind of checkpoint: how its errors name it ("checkpoint", "fit checkpoint"), and the
// format and version its preamble carries.
struct CheckpointKind {
  const char* label;
  const char* format;
  int version;
};

// {"format": kind.format, "version": kind.version}: the object a checkpoint's fields join.
[[nodiscard]] nlohmann::json checkpoint_preamble(const CheckpointKind& kind);

// The JSON of the checkpoint `path`, its preamble checked. Throws an Error
// "LABEL PATH: REASON" when the file cannot be opened, is not JSON, or is not an object of
// this kind's format and version.
[[nodiscard]] nlohmann::json read_checkpoint_json(const std::filesystem::path& path, const CheckpointKind& kind);

inline nlohmann::json json_number(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

// A number written by json_number; empty for anything else (the caller names the field).
inline std::optional<double> json_real(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  if (!j.is_string()) return std::nullopt;
  const auto& s = j.get_ref<const std::string&>();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  return std::nullopt;
}

inline nlohmann::json json_vector(const Eigen::VectorXd& v) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(json_number(v[i]));
  return out;
}

// A matrix as an array of its columns.
inline nlohmann::json json_columns(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index j = 0; j < m.cols(); ++j) out.push_back(json_vector(m.col(j)));
  return out;
}

}  // namespace yarnfit::swarm
