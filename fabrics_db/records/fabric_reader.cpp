// fabric.yaml: structure, keys, units and cross-checks (SPEC §2).
#include "fabrics_db/records/fabric_reader.hpp"

#include <cmath>
#include <set>
#include <stdexcept>
#include <algorithm>
#include <cctype>

#include <yaml-cpp/yaml.h>

#include "fabrics_db/text_util.hpp"
#include "fabrics_db/records/units.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

namespace fs = std::filesystem;

using units::k_gsm;
using units::k_mm;
constexpr double k_mass_fraction_tolerance = 0.01;

// Walks one fabric.yaml, turning every problem into a Problem with the key's line.
class YamlChecker {
 public:
  YamlChecker(std::string file, Problems& problems) : m_file(std::move(file)), m_problems(problems) {}

  void problem(const YAML::Node& at, const std::string& field, const std::string& message) {
    m_problems.add(m_file, line_of(at), field, message);
  }

  static int line_of(const YAML::Node& node) {
    if (!node.IsDefined()) return 0;
    const auto mark = node.Mark();
    return mark.line >= 0 ? mark.line + 1 : 0;
  }

  // Checks that `map` is a mapping with only `allowed` keys and no key twice. Returns false
  // (after recording a problem) when `map` is not a mapping.
  bool check_map(const YAML::Node& map, const std::string& path,
                 const std::vector<std::string>& allowed) {
    if (!map.IsMap()) {
      problem(map, path, std::string("expected a mapping of keys (") + join_words(allowed, ", ") +
                             "), got " + kind(map));
      return false;
    }
    std::set<std::string> seen;
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      const std::string field = path.empty() ? key : path + "." + key;
      if (!seen.insert(key).second) problem(kv.first, field, "duplicate key");
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string hint = closest_match(key, allowed);
        hint = hint.empty() ? "" : " (did you mean '" + hint + "'?)";
        problem(kv.first, field, "unknown key" + hint + "; allowed here: " + join_words(allowed, ", "));
      }
    }
    return true;
  }

  // The node under `key`, with its key node for line numbers.
  static std::pair<YAML::Node, YAML::Node> find(const YAML::Node& map, const std::string& key) {
    for (const auto& kv : map) {
      if (kv.first.Scalar() == key) return {kv.first, kv.second};
    }
    return {YAML::Node(YAML::NodeType::Undefined), YAML::Node(YAML::NodeType::Undefined)};
  }

  bool require(const YAML::Node& map, const std::string& key, const std::string& path) {
    if (find(map, key).second.IsDefined()) return true;
    problem(map, join(path, key), "missing required key");
    return false;
  }

  std::optional<std::string> text(const YAML::Node& map, const std::string& key,
                                  const std::string& path, bool required) {
    const auto [k, v] = find(map, key);
    if (!v.IsDefined()) {
      if (required) problem(map, join(path, key), "missing required key");
      return std::nullopt;
    }
    if (!v.IsScalar() || trim(v.Scalar()).empty()) {
      problem(k, join(path, key), "expected a non-empty text value, got " + kind(v));
      return std::nullopt;
    }
    if (std::size_t at = 0; !valid_utf8(v.Scalar(), &at)) {
      problem(k, join(path, key), "not valid UTF-8 text (byte " + std::to_string(at + 1) + " of the value)");
      return std::nullopt;
    }
    return v.Scalar();
  }

  // A finite number; `positive` rejects values ≤ 0.
  std::optional<double> number(const YAML::Node& map, const std::string& key,
                               const std::string& path, bool required, bool positive) {
    const auto [k, v] = find(map, key);
    const std::string field = join(path, key);
    if (!v.IsDefined()) {
      if (required) problem(map, field, "missing required key");
      return std::nullopt;
    }
    if (!v.IsScalar()) {
      problem(k, field, "expected a number, got " + kind(v));
      return std::nullopt;
    }
    std::string why;
    std::string s = v.Scalar();
    if (s == ".nan" || s == ".NaN" || s == ".NAN") s = "nan";
    if (s == ".inf" || s == "-.inf" || s == "+.inf") s = "inf";
    const auto value = parse_finite_number(s, why);
    if (!value) {
      problem(k, field, why);
      return std::nullopt;
    }
    if (positive && *value <= 0.0) {
      problem(k, field, "must be positive, got " + v.Scalar());
      return std::nullopt;
    }
    return value;
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  static std::string kind(const YAML::Node& n) {
    switch (n.Type()) {
      case YAML::NodeType::Null: return "an empty value";
      case YAML::NodeType::Scalar: return "'" + n.Scalar() + "'";
      case YAML::NodeType::Sequence: return "a list";
      case YAML::NodeType::Map: return "a mapping";
      default: return "nothing";
    }
  }

  [[nodiscard]] const std::string& file() const { return m_file; }

 private:
  std::string m_file;
  Problems& m_problems;
};

const std::vector<std::string> k_top_keys{
    "id",      "family",         "description",  "areal_density_gsm", "yarns",         "pattern",
    "swatch",  "knitting_gauge", "thickness_mm", "stretch_tests",     "bending_tests", "fab_tests",
    "ground_truth"};
const std::vector<std::string> k_fab_test_keys{"file",         "clamp_distance_mm", "strip_width_mm", "zero_offset_N",
                                               "sampling_hz", "test_version",      "time_utc"};
const std::vector<std::string> k_fab_source_keys{"file", "serial", "hardware_version", "build"};
const std::vector<std::string> k_knitting_gauge_keys{"courses_per_10cm", "wales_per_10cm"};
const std::vector<std::string> k_yarn_keys{"material", "denier", "filaments", "mass_fraction",
                                           "stiffness_N"};
const std::vector<std::string> k_size_keys{"length_mm", "width_mm"};
const std::vector<std::string> k_stretch_keys{"file", "swatch", "gauge"};
const std::vector<std::string> k_bending_keys{"file", "swatch"};
const std::vector<std::string> k_pattern_keys{"file", "weft_axis", "knit", "stitch_length_mm", "yarn_radius_mm"};
const std::vector<std::string> k_direction_names{"weft", "bias", "warp"};

std::optional<Swatch> read_swatch(YamlChecker& y, const YAML::Node& node, const std::string& path) {
  if (!y.check_map(node, path, k_size_keys)) return std::nullopt;
  const auto length = y.number(node, "length_mm", path, true, true);
  const auto width = y.number(node, "width_mm", path, true, true);
  if (!length || !width) return std::nullopt;
  return Swatch{*length * k_mm, *width * k_mm};
}

// `knitting_gauge: {courses_per_10cm, wales_per_10cm}`: both, each positive.
std::optional<KnittingGauge> read_knitting_gauge(YamlChecker& y, const YAML::Node& node) {
  if (!y.check_map(node, "knitting_gauge", k_knitting_gauge_keys)) return std::nullopt;
  const auto courses = y.number(node, "courses_per_10cm", "knitting_gauge", true, true);
  const auto wales = y.number(node, "wales_per_10cm", "knitting_gauge", true, true);
  if (!courses || !wales) return std::nullopt;
  return KnittingGauge{*courses, *wales};
}

std::optional<Gauge> read_gauge(YamlChecker& y, const YAML::Node& node, const std::string& path) {
  if (!y.check_map(node, path, k_size_keys)) return std::nullopt;
  Gauge g;
  bool ok = true;
  for (const char* key : {"length_mm", "width_mm"}) {
    if (!YamlChecker::find(node, key).second.IsDefined()) continue;
    const auto v = y.number(node, key, path, false, true);
    if (!v) ok = false;
    (std::string(key) == "length_mm" ? g.length : g.width) = v ? std::optional(*v * k_mm) : std::nullopt;
  }
  if (!ok) return std::nullopt;
  return g;
}

// The file named under `file`, inside the record's folder (SPEC §2). A problem names the field
// and the name as written, never the folder's place on the disk nor anything of another file.
std::optional<fs::path> read_file_ref(YamlChecker& y, const YAML::Node& map, const std::string& path,
                                      const fs::path& folder) {
  const auto name = y.text(map, "file", path, true);
  if (!name) return std::nullopt;
  std::string why;
  fs::path file = file_inside_folder(folder, *name, why);
  if (file.empty()) {
    y.problem(YamlChecker::find(map, "file").first, YamlChecker::join(path, "file"), why);
    return std::nullopt;
  }
  return file;
}

void read_yarns(YamlChecker& y, const YAML::Node& doc, Fabric& fabric) {
  const auto [key, list] = YamlChecker::find(doc, "yarns");
  if (!list.IsDefined()) {
    y.problem(doc, "yarns", "missing required key (list the yarns of the fabric)");
    return;
  }
  if (!list.IsSequence() || list.size() == 0) {
    y.problem(key, "yarns", "expected a non-empty list of yarns, got " + YamlChecker::kind(list));
    return;
  }
  double fraction_sum = 0.0;
  bool fractions_ok = true;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node node = list[i];
    const std::string path = "yarns[" + std::to_string(i) + "]";
    if (!y.check_map(node, path, k_yarn_keys)) {
      fractions_ok = false;
      continue;
    }
    YarnSpec yarn;
    const auto material = y.text(node, "material", path, true);
    const auto denier = y.number(node, "denier", path, true, true);
    const auto fraction = y.number(node, "mass_fraction", path, true, true);
    const auto stiffness = y.number(node, "stiffness_N", path, false, true);
    const auto filaments = y.number(node, "filaments", path, false, true);
    if (filaments && *filaments != std::floor(*filaments)) {
      y.problem(YamlChecker::find(node, "filaments").first, path + ".filaments",
                "must be a whole number, got " + format_g(*filaments));
    }
    if (fraction && *fraction > 1.0) {
      y.problem(YamlChecker::find(node, "mass_fraction").first, path + ".mass_fraction",
                "a mass fraction is at most 1, got " + format_g(*fraction) +
                    " (write 0.9, not 90)");
    }
    if (!fraction) fractions_ok = false;
    fraction_sum += fraction.value_or(0.0);
    yarn.material = material.value_or("");
    yarn.denier = denier.value_or(0.0);
    yarn.mass_fraction = fraction.value_or(0.0);
    yarn.stiffness = stiffness;
    if (filaments) yarn.filaments = static_cast<int>(*filaments);
    fabric.yarns.push_back(yarn);
  }
  if (fractions_ok && std::abs(fraction_sum - 1.0) > k_mass_fraction_tolerance) {
    y.problem(key, "yarns", "mass fractions sum to " + format_g(fraction_sum, 4) +
                                ", expected 1 (±" + format_g(k_mass_fraction_tolerance) + ")");
  }
}

void read_pattern(YamlChecker& y, const YAML::Node& doc, Fabric& fabric, Problems& problems) {
  const auto [key, node] = YamlChecker::find(doc, "pattern");
  if (!node.IsDefined()) return;
  if (!y.check_map(node, "pattern", k_pattern_keys)) return;
  PatternRef ref;
  if (const auto axis = y.text(node, "weft_axis", "pattern", false)) {
    if (*axis == "x") ref.weft_axis = Axis::x;
    else if (*axis == "y") ref.weft_axis = Axis::y;
    else y.problem(YamlChecker::find(node, "weft_axis").first, "pattern.weft_axis",
                   "expected x or y, got '" + *axis + "'");
  }
  const bool has_file = YamlChecker::find(node, "file").second.IsDefined();
  const auto [knit_key, knit_node] = YamlChecker::find(node, "knit");
  if (knit_node.IsDefined()) {
    // A generated tile: the chart, the yarn length per stitch and the yarn radius.
    if (has_file) y.problem(knit_key, "pattern.knit", "give either file (a tile) or knit (a tile to generate), not both");
    const auto chart_text = y.text(node, "knit", "pattern", true);
    const auto length = y.number(node, "stitch_length_mm", "pattern", true, true);
    const auto radius = y.number(node, "yarn_radius_mm", "pattern", true, true);
    std::optional<KnitChart> chart;
    if (chart_text) {
      std::string why;
      chart = parse_knit_chart(*chart_text, &why);
      if (!chart) y.problem(knit_node, "pattern.knit", why);
    }
    if (has_file || !chart || !length || !radius) return;
    ref.knit = KnitSpec{*chart, *length * k_mm, *radius * k_mm, std::nullopt};
    fabric.pattern = std::move(ref);
    return;
  }
  for (const char* knit_only : {"stitch_length_mm", "yarn_radius_mm"}) {
    const auto [k, v] = YamlChecker::find(node, knit_only);
    if (v.IsDefined()) y.problem(k, std::string("pattern.") + knit_only, "only with knit (a tile to generate)");
  }
  const auto file = read_file_ref(y, node, "pattern", fabric.folder);
  if (!file) return;
  Problems tile_problems;
  auto tile = read_pyp(*file, tile_problems);
  if (!tile) {
    y.problem(YamlChecker::find(node, "file").first, "pattern.file",
              "unreadable pattern '" + node["file"].Scalar() + "' (" + std::to_string(tile_problems.size()) +
                  " problem" + (tile_problems.size() == 1 ? "" : "s") + ", listed below)");
    problems.append(tile_problems);
    return;
  }
  // The tile's facts (R_est) are computed from its geometry; a geometry no knit could have,
  // such as edges spanning thousands of periods, is an input problem, not a crash later.
  try {
    ref.facts = compute_tile_facts(*tile);
  } catch (const Error& e) {
    y.problem(YamlChecker::find(node, "file").first, "pattern.file",
              "pattern '" + node["file"].Scalar() + "' has an impossible geometry: " + e.what());
    return;
  }
  ref.file = *file;
  ref.tile = std::move(*tile);
  fabric.pattern = std::move(ref);
}

// Iterates the directions of `stretch_tests` or `bending_tests`, rejecting unknown ones.
template <typename Fn>
void for_each_direction(YamlChecker& y, const YAML::Node& node, const std::string& path, Fn&& fn) {
  if (!node.IsMap()) {
    y.problem(node, path, "expected a mapping of directions (weft, bias, warp), got " +
                              YamlChecker::kind(node));
    return;
  }
  std::set<std::string> seen;
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    const std::string field = path + "." + name;
    if (!seen.insert(name).second) {
      y.problem(kv.first, field, "duplicate direction");
      continue;
    }
    const auto dir = parse_direction(name);
    if (!dir) {
      std::string hint = closest_match(name, k_direction_names);
      hint = hint.empty() ? "" : " (did you mean '" + hint + "'?)";
      y.problem(kv.first, field, "unknown direction" + hint + "; expected weft, bias or warp");
      continue;
    }
    fn(*dir, kv.first, kv.second, field);
  }
}

// The swatch a test uses: its own, else the fabric's.
std::optional<Swatch> test_swatch(YamlChecker& y, const Fabric& fabric, bool fabric_swatch_given,
                                  const YAML::Node& key, const YAML::Node& test,
                                  const std::string& field, bool& ok) {
  if (const auto own = YamlChecker::find(test, "swatch").second; own.IsDefined()) {
    auto s = read_swatch(y, own, field + ".swatch");
    if (!s) ok = false;
    return s;
  }
  if (fabric.swatch) return fabric.swatch;
  ok = false;
  // A top-level swatch that is present but invalid was reported already; say nothing more.
  if (fabric_swatch_given) return std::nullopt;
  y.problem(key, field, "no swatch size: give swatch {length_mm, width_mm} here or at the top level");
  return std::nullopt;
}

void read_stretch_tests(YamlChecker& y, const YAML::Node& doc, Fabric& fabric, Problems& problems) {
  const bool swatch_given = YamlChecker::find(doc, "swatch").second.IsDefined();
  const auto [key, node] = YamlChecker::find(doc, "stretch_tests");
  if (!node.IsDefined()) {
    y.problem(doc, "stretch_tests", "missing required key (at least one of weft, bias, warp)");
    return;
  }
  if (node.IsMap() && node.size() == 0) {
    y.problem(key, "stretch_tests", "no test given (expected at least one of weft, bias, warp)");
    return;
  }
  for_each_direction(y, node, "stretch_tests", [&](Direction dir, const YAML::Node& dkey,
                                                   const YAML::Node& test, const std::string& field) {
    if (!y.check_map(test, field, k_stretch_keys)) return;
    bool ok = true;
    StretchTest st;
    st.direction = dir;
    const auto swatch = test_swatch(y, fabric, swatch_given, dkey, test, field, ok);
    if (const auto g = YamlChecker::find(test, "gauge").second; g.IsDefined()) {
      const auto gauge = read_gauge(y, g, field + ".gauge");
      if (!gauge) ok = false;
      else st.gauge = *gauge;
      // Marks must sit on the fabric between the clamps.
      if (gauge && swatch) {
        if (gauge->length && *gauge->length >= swatch->length)
          y.problem(YamlChecker::find(g, "length_mm").first, field + ".gauge.length_mm",
                    "gauge length " + format_g(*gauge->length / k_mm) +
                        " mm must be shorter than the free length between the clamps (" +
                        format_g(swatch->length / k_mm) + " mm)");
        if (gauge->width && *gauge->width > swatch->width)
          y.problem(YamlChecker::find(g, "width_mm").first, field + ".gauge.width_mm",
                    "gauge width " + format_g(*gauge->width / k_mm) +
                        " mm is wider than the swatch (" + format_g(swatch->width / k_mm) + " mm)");
      }
    }
    const auto file = read_file_ref(y, test, field, fabric.folder);
    if (!file) return;
    const auto table = read_csv(*file, CsvOptions{}, problems);
    if (!table) return;
    auto curve = read_stretch_curve(*table, problems);
    if (!curve || !ok || !swatch) return;
    st.file = *file;
    st.swatch = *swatch;
    st.curve = std::move(*curve);
    fabric.stretch_tests.emplace(dir, std::move(st));
  });
}

void read_bending_tests(YamlChecker& y, const YAML::Node& doc, Fabric& fabric, Problems& problems) {
  const bool swatch_given = YamlChecker::find(doc, "swatch").second.IsDefined();
  const auto [key, node] = YamlChecker::find(doc, "bending_tests");
  if (!node.IsDefined()) return;
  if (!fabric.areal_density && !YamlChecker::find(doc, "areal_density_gsm").second.IsDefined()) {
    y.problem(key, "areal_density_gsm",
              "required when bending_tests are given: the pear loop hangs under its own weight");
  }
  for_each_direction(y, node, "bending_tests", [&](Direction dir, const YAML::Node& dkey,
                                                   const YAML::Node& test, const std::string& field) {
    if (!y.check_map(test, field, k_bending_keys)) return;
    bool ok = true;
    BendingTest bt;
    bt.direction = dir;
    const auto swatch = test_swatch(y, fabric, swatch_given, dkey, test, field, ok);
    const auto file = read_file_ref(y, test, field, fabric.folder);
    if (!file) return;
    const auto table = read_csv(*file, CsvOptions{}, problems);
    if (!table) return;
    auto curve = read_bending_curve(*table, problems);
    if (!curve || !ok || !swatch) return;
    bt.file = *file;
    bt.swatch = *swatch;
    bt.curve = std::move(*curve);
    fabric.bending_tests.emplace(dir, std::move(bt));
  });
}

std::optional<long long> whole_number(YamlChecker& y, const YAML::Node& map, const std::string& key,
                                      const std::string& path) {
  const auto v = y.number(map, key, path, false, false);
  if (!v) return std::nullopt;
  if (*v != std::floor(*v) || std::abs(*v) > 9e15) {
    y.problem(YamlChecker::find(map, key).first, YamlChecker::join(path, key), "expected a whole number");
    return std::nullopt;
  }
  return static_cast<long long>(*v);
}

// fab_tests (docs/fab.md): the FAB's tests per direction, each with its samples' CSV.
void read_fab_tests(YamlChecker& y, const YAML::Node& doc, Fabric& fabric, Problems& problems) {
  const auto [key, node] = YamlChecker::find(doc, "fab_tests");
  if (!node.IsDefined()) return;
  if (!node.IsMap()) {
    y.problem(key, "fab_tests", "expected a mapping of source and directions, got " + YamlChecker::kind(node));
    return;
  }
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    const std::string field = "fab_tests." + name;
    if (name == "source") {
      if (!y.check_map(kv.second, field, k_fab_source_keys)) continue;
      FabSource src;
      if (YamlChecker::find(kv.second, "file").second.IsDefined()) {
        const auto file = read_file_ref(y, kv.second, field, fabric.folder);
        if (file) src.file = *file;
      }
      src.serial = whole_number(y, kv.second, "serial", field);
      src.hardware_version = whole_number(y, kv.second, "hardware_version", field);
      src.build = whole_number(y, kv.second, "build", field);
      fabric.fab_source = src;
      continue;
    }
    const auto dir = parse_direction(name);
    if (!dir) {
      std::string hint = closest_match(name, {"source", "weft", "bias", "warp"});
      hint = hint.empty() ? "" : " (did you mean '" + hint + "'?)";
      y.problem(kv.first, field, "unknown key" + hint + "; expected source, weft, bias or warp");
      continue;
    }
    if (!kv.second.IsMap()) {
      y.problem(kv.first, field, "expected a mapping of FAB tests (S1, S2, U1, D1, D2), got " + YamlChecker::kind(kv.second));
      continue;
    }
    auto& tests = fabric.fab_tests[*dir];
    for (const auto& tkv : kv.second) {
      const std::string tname = tkv.first.Scalar();
      const std::string tfield = field + "." + tname;
      const FabTestName* spec = find_fab_test(tname);
      if (!spec) {
        y.problem(tkv.first, tfield, "unknown FAB test; expected S1, S2, U1, D1 or D2");
        continue;
      }
      if (std::any_of(tests.begin(), tests.end(), [&](const FabTest& t) { return t.name == tname; })) {
        y.problem(tkv.first, tfield, "duplicate test");
        continue;
      }
      if (!y.check_map(tkv.second, tfield, k_fab_test_keys)) continue;
      FabTest t;
      t.name = tname;
      t.kind = spec->kind;
      const auto distance = y.number(tkv.second, "clamp_distance_mm", tfield, true, true);
      const auto width = y.number(tkv.second, "strip_width_mm", tfield, true, true);
      t.zero_offset = y.number(tkv.second, "zero_offset_N", tfield, false, false);
      if (const auto hz = whole_number(y, tkv.second, "sampling_hz", tfield)) t.sampling_hz = static_cast<int>(*hz);
      t.test_version = whole_number(y, tkv.second, "test_version", tfield);
      y.text(tkv.second, "time_utc", tfield, false);
      const auto file = read_file_ref(y, tkv.second, tfield, fabric.folder);
      if (!file || !distance || !width) continue;
      const auto table = read_csv(*file, CsvOptions{}, problems);
      if (!table) continue;
      auto branches = read_fab_test_curve(*table, problems);
      if (!branches) continue;
      t.file = *file;
      t.clamp_distance = *distance * k_mm;
      t.strip_width = *width * k_mm;
      t.branches = std::move(*branches);
      tests.push_back(std::move(t));
    }
    // Protocol order, whatever the file's.
    std::sort(tests.begin(), tests.end(), [](const FabTest& a, const FabTest& b) {
      return find_fab_test(a.name) < find_fab_test(b.name);
    });
  }
}

nlohmann::json to_json(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      nlohmann::json j = nlohmann::json::object();
      for (const auto& kv : node) j[kv.first.Scalar()] = to_json(kv.second);
      return j;
    }
    case YAML::NodeType::Sequence: {
      nlohmann::json j = nlohmann::json::array();
      for (const auto& item : node) j.push_back(to_json(item));
      return j;
    }
    case YAML::NodeType::Scalar: {
      std::string why;
      if (const auto v = parse_finite_number(node.Scalar(), why)) return *v;
      if (node.Scalar() == "true") return true;
      if (node.Scalar() == "false") return false;
      return node.Scalar();
    }
    default: return nullptr;
  }
}

bool valid_id(const std::string& id) {
  return !id.empty() && std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
  });
}

}  // namespace

bool is_fabric_folder(const fs::path& folder) {
  std::error_code ec;
  return fs::is_regular_file(folder / k_fabric_file_name, ec);
}

FabricLoad load_fabric(const fs::path& folder) {
  FabricLoad load;
  load.folder = folder;
  const fs::path yaml_path = folder / k_fabric_file_name;
  const std::string label = yaml_path.string();

  std::string text;
  if (std::string why; !read_text_file(yaml_path, text, why)) {
    load.problems.add(label, 0, "file", why);
    return load;
  }
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    load.problems.add(label, e.mark.line >= 0 ? e.mark.line + 1 : 0, "yaml",
                      "malformed YAML: " + e.msg);
    return load;
  }

  YamlChecker y(label, load.problems);
  if (!doc.IsMap()) {
    load.problems.add(label, 1, "file", "expected a mapping of keys at the top level, got " +
                                            YamlChecker::kind(doc));
    return load;
  }
  y.check_map(doc, "", k_top_keys);

  Fabric fabric;
  fabric.folder = folder;
  if (const auto id = y.text(doc, "id", "", true)) {
    if (!valid_id(*id))
      y.problem(YamlChecker::find(doc, "id").first, "id",
                "'" + *id + "' may use only letters, digits, '-', '_' and '.'");
    fabric.id = *id;
  }
  fabric.family = y.text(doc, "family", "", true).value_or("");
  fabric.description = y.text(doc, "description", "", false).value_or("");
  load.id = fabric.id;
  load.id_line = YamlChecker::line_of(YamlChecker::find(doc, "id").first);
  load.family = fabric.family;
  if (const auto rho = y.number(doc, "areal_density_gsm", "", false, true)) {
    fabric.areal_density = *rho * k_gsm;
  }
  read_yarns(y, doc, fabric);
  if (const auto s = YamlChecker::find(doc, "swatch").second; s.IsDefined()) {
    fabric.swatch = read_swatch(y, s, "swatch");
  }
  if (const auto g = YamlChecker::find(doc, "knitting_gauge").second; g.IsDefined())
    fabric.knitting_gauge = read_knitting_gauge(y, g);
  if (const auto t = y.number(doc, "thickness_mm", "", false, true)) fabric.thickness = *t * k_mm;
  read_pattern(y, doc, fabric, load.problems);
  if (fabric.pattern && fabric.pattern->knit) fabric.pattern->knit->gauge = fabric.knitting_gauge;
  read_stretch_tests(y, doc, fabric, load.problems);
  read_bending_tests(y, doc, fabric, load.problems);
  read_fab_tests(y, doc, fabric, load.problems);
  if (const auto gt = YamlChecker::find(doc, "ground_truth"); gt.second.IsDefined()) {
    if (!gt.second.IsMap() && !gt.second.IsNull())
      y.problem(gt.first, "ground_truth", "expected a mapping of parameter names to values");
    else
      fabric.ground_truth = gt.second.IsNull() ? nlohmann::json::object() : to_json(gt.second);
  }

  if (load.problems.empty()) load.fabric = std::move(fabric);
  return load;
}

}  // namespace yarnfit::db
