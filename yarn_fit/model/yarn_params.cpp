#include "yarn_fit/model/yarn_params.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

namespace yarnfit::yarn {

db::Problems YarnParams::problems() const {
  db::Problems out;
  const std::array<std::pair<const char*, double>, 7> positive{
      {{"ks1", ks1}, {"kb", kb}, {"R1", r1}, {"kc1", kc1}, {"ks2", ks2}, {"kc2", kc2}, {"R2", r2}}};
  for (const auto& [key, value] : positive) {
    if (!std::isfinite(value) || value <= 0.0)
      out.add_field(key, "must be a finite value > 0, got " + std::to_string(value));
  }
  if (!std::isfinite(eps_s) || eps_s < 0.0)
    out.add_field("eps_s", "must be a finite value >= 0, got " + std::to_string(eps_s));
  if (ks1 > ks2) out.add_field("ks1", "must not exceed ks2 (the stiff phase is the stiffer one)");
  if (r2 >= r1) out.add_field("R2", "must be smaller than R1 (the stiff barrier is the inner one)");
  return out;
}

const char* to_string(YarnParam p) {
  switch (p) {
    case YarnParam::ks1: return "ks1";
    case YarnParam::eps_s: return "eps_s";
    case YarnParam::kb: return "kb";
    case YarnParam::r1: return "R1";
    case YarnParam::kc1: return "kc1";
    case YarnParam::ks2: return "ks2";
    case YarnParam::kc2: return "kc2";
    case YarnParam::r2: return "R2";
  }
  return "unknown";
}

std::optional<YarnParam> yarn_param_from_string(std::string_view name) {
  for (const YarnParam p : kAllYarnParams)
    if (name == to_string(p)) return p;
  return std::nullopt;
}

namespace {
double YarnParams::*field_of(YarnParam p) {
  switch (p) {
    case YarnParam::ks1: return &YarnParams::ks1;
    case YarnParam::eps_s: return &YarnParams::eps_s;
    case YarnParam::kb: return &YarnParams::kb;
    case YarnParam::r1: return &YarnParams::r1;
    case YarnParam::kc1: return &YarnParams::kc1;
    case YarnParam::ks2: return &YarnParams::ks2;
    case YarnParam::kc2: return &YarnParams::kc2;
    case YarnParam::r2: return &YarnParams::r2;
  }
  return &YarnParams::ks1;
}
}  // namespace

double get(const YarnParams& params, YarnParam p) { return params.*field_of(p); }
void set(YarnParams& params, YarnParam p, double value) { params.*field_of(p) = value; }

YarnParams default_params(const ParameterScales& scales) {
  YarnParams p;
  p.ks2 = scales.ks2;
  p.ks1 = 0.03 * scales.ks2;
  p.eps_s = 0.075;
  p.kb = 0.1 * scales.kb_base();
  p.r1 = scales.r_est;
  p.kc1 = scales.kc_base();
  p.kc2 = scales.kc2();
  p.r2 = scales.r2();
  return p;
}

nlohmann::json to_json(const YarnParams& p) {
  return nlohmann::json{{"ks1", p.ks1}, {"eps_s", p.eps_s}, {"kb", p.kb}, {"R1", p.r1},
                        {"kc1", p.kc1}, {"ks2", p.ks2},     {"kc2", p.kc2}, {"R2", p.r2}};
}

namespace {

// The file as a YAML mapping, or nothing with its problem.
std::optional<YAML::Node> load_mapping(const std::filesystem::path& file, const std::string& label,
                                       db::Problems& problems) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    problems.add(label, 0, "file", "cannot read the yarn parameter file");
    return std::nullopt;
  } catch (const YAML::ParserException& e) {
    problems.add(label, e.mark.line + 1, "file", "not valid YAML: " + e.msg);
    return std::nullopt;
  }
  if (!doc.IsMap()) {
    problems.add(label, doc.Mark().line + 1, "file",
                 "expected a mapping of yarn parameters (ks1, eps_s, kb, R1, kc1, ks2, kc2, R2)");
    return std::nullopt;
  }
  return doc;
}

using ParamKeys = std::array<std::pair<const char*, double*>, 8>;

// The keys that are not parameters: a mapping or list as a key ("? [a, b]: 1", "{a: 1}: 2"), and
// an unknown name in a parameter file (a yarn_fit.json's `params` sits among other keys).
void report_stray_keys(const YAML::Node& root, bool parameter_file, const ParamKeys& keys,
                       const std::string& label, db::Problems& problems) {
  for (const auto& entry : root) {
    if (!entry.first.IsScalar()) {
      problems.add(label, entry.first.Mark().line + 1, "file", "a key must be a parameter name, not a mapping or list");
      continue;
    }
    const std::string key = entry.first.Scalar();
    bool known = false;
    for (const auto& [name, target] : keys) known = known || key == name;
    if (!known && parameter_file)
      problems.add(label, entry.first.Mark().line + 1, key,
                   "unknown key; expected ks1, eps_s, kb, R1, kc1, ks2, kc2, R2");
  }
}

// One parameter: the file's finite number, or, where the file leaves ks2, kc2 or R2 out and
// scales are given, the scales' value.
void read_value(const YAML::Node& root, const std::string& name, const std::optional<ParameterScales>& scales,
                double& target, const std::string& label, db::Problems& problems) {
  const YAML::Node node = root[name];
  if (!node) {
    if (scales && name == "ks2") {
      target = scales->ks2;
    } else if (scales && name == "kc2") {
      target = scales->kc2();
    } else if (scales && name == "R2") {
      target = scales->r2();
    } else {
      problems.add(label, root.Mark().line + 1, name, "missing");
    }
    return;
  }
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    problems.add(label, node.Mark().line + 1, name, "expected a number in SI units");
    return;
  }
  if (!std::isfinite(value)) {
    problems.add(label, node.Mark().line + 1, name, "must be finite");
    return;
  }
  target = value;
}

}  // namespace

std::optional<YarnParams> read_yarn_params(const std::filesystem::path& file,
                                           const std::optional<ParameterScales>& scales,
                                           db::Problems& problems) {
  const std::string label = file.string();
  const std::optional<YAML::Node> doc = load_mapping(file, label, problems);
  if (!doc) return std::nullopt;
  // A yarn_fit.json may be passed directly: read its `params`.
  const YAML::Node root = (*doc)["params"] && (*doc)["params"].IsMap() ? (*doc)["params"] : *doc;

  YarnParams p;
  const ParamKeys keys{{{"ks1", &p.ks1},
                        {"eps_s", &p.eps_s},
                        {"kb", &p.kb},
                        {"R1", &p.r1},
                        {"kc1", &p.kc1},
                        {"ks2", &p.ks2},
                        {"kc2", &p.kc2},
                        {"R2", &p.r2}}};
  const std::size_t before = problems.size();
  report_stray_keys(root, root == *doc, keys, label, problems);
  for (const auto& [name, target] : keys) read_value(root, name, scales, *target, label, problems);
  if (problems.size() != before) return std::nullopt;
  if (const db::Problems invalid = p.problems(); !invalid.empty()) {
    for (const auto& q : invalid.items()) problems.add(label, root.Mark().line + 1, q.field, q.message);
    return std::nullopt;
  }
  return p;
}

}  // namespace yarnfit::yarn
