// U3M 1.1 physics (Browzwear FAB raw data) → FabMeasurement, every problem with its JSON path.
#include "fabrics_db/fab/fab_physics.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <archive.h>
#include <archive_entry.h>

#include "fabrics_db/csv/csv_table.hpp"
#include "fabrics_db/text_util.hpp"
#include "fabrics_db/records/units.hpp"

namespace yarnfit::db {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double k_cm = 1e-2;
using units::k_gsm;
constexpr double k_slack_fraction = 0.005;  // a sample 0.5 % below the taut length is slack
constexpr std::uintmax_t k_max_file_bytes = 64u << 20;

// "[json.exception.out_of_range.406] number overflow …" → "number overflow …".
std::string plain(std::string what) {
  if (const auto at = what.find("] "); what.rfind("[json.exception", 0) == 0 && at != std::string::npos)
    what = what.substr(at + 2);
  return what;
}

// The JSON path of a syntax error: a SAX pass that keeps the keys and indices on the way.
class PathTracker : public json::json_sax_t {
 public:
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t v, const string_t& text) override {
    if (std::isfinite(v)) return value();
    value();
    m_message = "number out of range: " + text.substr(0, 40);
    m_at_value = true;
    return false;
  }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    enter();
    m_frames.push_back({false, -1, ""});
    return true;
  }
  bool key(string_t& k) override {
    m_frames.back().key = k;
    return true;
  }
  bool end_object() override {
    m_frames.pop_back();
    return true;
  }
  bool start_array(std::size_t) override {
    enter();
    m_frames.push_back({true, -1, ""});
    return true;
  }
  bool end_array() override {
    m_frames.pop_back();
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    m_position = position;
    m_message = plain(e.what());
    if (const auto at = m_message.find("syntax error"); at != std::string::npos) m_message = m_message.substr(at);
    // The failing value's place: the next element of an array, the current key of an object.
    if (!m_frames.empty() && m_frames.back().array) ++m_frames.back().index;
    return false;
  }
  [[nodiscard]] std::string path() const {
    std::string p;
    for (const auto& f : m_frames) {
      p += "/" + (f.array ? std::to_string(std::max(f.index, 0)) : f.key.substr(0, 40));
      if (p.size() > 200) return p.substr(0, 200) + "…";
    }
    return p.empty() ? "/" : p;
  }
  std::size_t m_position = 0;
  std::string m_message;
  bool m_at_value = false;  // stopped at a value it refused (not at a syntax error)

 private:
  struct Frame {
    bool array;
    int index;
    std::string key;
  };
  bool value() {
    if (!m_frames.empty() && m_frames.back().array) ++m_frames.back().index;
    return true;
  }
  void enter() { value(); }
  std::vector<Frame> m_frames;
};

int line_at(std::string_view text, std::size_t position) {
  position = std::min(position, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(position), '\n'));
}

std::optional<json> parse_json(std::string_view text, const std::string& label, Problems& problems) {
  try {
    return json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {
    // Again, keeping the keys and indices on the way, to say where (a number too large for a
    // double is not a syntax error: the DOM parser throws out_of_range for it).
    PathTracker t;
    try {
      json::sax_parse(text.begin(), text.end(), &t);
    } catch (const json::exception& inner) {
      if (t.m_message.empty()) t.m_message = plain(inner.what());
    }
    std::string why = t.m_message.empty() ? plain(e.what()) : t.m_message;
    // A bare NaN or Infinity stops the lexer at its first letter ("last read: '… [N'").
    const auto read = why.find("last read: '");
    const char last = read != std::string::npos && why.find('\'', read + 12) != std::string::npos
                          ? why[why.find('\'', read + 12) - 1]
                          : ' ';
    const bool nan_like = why.find("invalid literal") != std::string::npos && (last == 'N' || last == 'I');
    problems.add(label, line_at(text, t.m_position), t.path(),
                 "malformed JSON (" + why + ")" +
                     (nan_like ? "; a bare NaN or Infinity is not JSON: numbers must be finite JSON numbers" : ""));
    return std::nullopt;
  }
}

std::string describe(const json& v) {
  if (v.is_string()) {
    std::string t = v.get<std::string>();
    if (t.size() > 40) {
      std::size_t cut = 40;
      while (cut > 0 && (static_cast<unsigned char>(t[cut]) & 0xC0) == 0x80) --cut;  // not inside a character
      t = t.substr(0, cut) + "…";
    }
    return "text \"" + t + "\"";
  }
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_array()) return "a list";
  if (v.is_object()) return "an object";
  return "a number";
}

// Reads the fields of raw_data, adding a problem for each one missing or malformed.
class RawReader {
 public:
  RawReader(std::string label, Problems& problems) : m_label(std::move(label)), m_problems(problems) {}

  void problem(const std::string& path, const std::string& message) { m_problems.add(m_label, 0, path, message); }

  const json* object(const json& parent, const std::string& key, const std::string& path, const char* what) {
    const std::string p = path + "/" + key;
    const auto it = parent.find(key);
    if (it == parent.end()) {
      problem(p, std::string("missing: ") + what);
      return nullptr;
    }
    if (!it->is_object()) {
      problem(p, std::string("expected an object (") + what + "), got " + describe(*it));
      return nullptr;
    }
    return &*it;
  }

  // A number; `positive` rejects values <= 0. Numbers inside raw_data must be JSON numbers.
  std::optional<double> number(const json& parent, const std::string& key, const std::string& path, bool positive) {
    const std::string p = path + "/" + key;
    const auto it = parent.find(key);
    if (it == parent.end()) {
      problem(p, "missing required number");
      return std::nullopt;
    }
    if (!it->is_number()) {
      problem(p, "expected a number, got " + describe(*it));
      return std::nullopt;
    }
    const double v = it->get<double>();
    if (!std::isfinite(v)) {
      problem(p, "not a finite number");
      return std::nullopt;
    }
    if (positive && v <= 0.0) {
      problem(p, "must be positive, got " + format_g(v));
      return std::nullopt;
    }
    return v;
  }

  std::optional<long long> integer(const json& parent, const std::string& key, const std::string& path,
                                   bool required) {
    const auto it = parent.find(key);
    if (it == parent.end()) {
      if (required) problem(path + "/" + key, "missing required whole number");
      return std::nullopt;
    }
    if (!it->is_number_integer()) {
      problem(path + "/" + key, "expected a whole number, got " + describe(*it));
      return std::nullopt;
    }
    // Beyond ±9e15 a whole number does not survive a double (the record keeps it as one).
    if (it->is_number_unsigned() ? it->get<unsigned long long>() > 9'000'000'000'000'000ULL
                                 : std::llabs(it->get<long long>()) > 9'000'000'000'000'000LL) {
      problem(path + "/" + key, "whole number out of range: " + it->dump());
      return std::nullopt;
    }
    return it->get<long long>();
  }

  // samplesTree: lists of distance [cm], force [gf] pairs, alternating loading and relaxation.
  std::vector<FabBranchCurve> branches(const json& test, const std::string& path, bool pairs_of_branches) {
    std::vector<FabBranchCurve> out;
    const std::string p = path + "/samplesTree";
    const auto it = test.find("samplesTree");
    if (it == test.end()) {
      problem(p, "missing: the samples");
      return out;
    }
    if (!it->is_array() || it->empty()) {
      problem(p, "expected a non-empty list of sample lists, got " + (it->is_array() ? std::string("an empty list") : describe(*it)));
      return out;
    }
    if (pairs_of_branches && it->size() % 2 != 0)
      problem(p, std::to_string(it->size()) + " sample lists: expected a loading and a relaxation list per cycle (an even number)");
    bool ok = true;
    for (std::size_t b = 0; b < it->size(); ++b) {
      const json& list = (*it)[b];
      const std::string lp = p + "/" + std::to_string(b);
      if (!list.is_array()) {
        problem(lp, "expected a list of distance, force pairs, got " + describe(list));
        ok = false;
        continue;
      }
      if (list.size() % 2 != 0) {
        problem(lp, std::to_string(list.size()) + " numbers: expected distance, force pairs (an even count)");
        ok = false;
        continue;
      }
      // A test's branch is a curve (2 samples at least); the thickness test may stop at one.
      const std::size_t fewest = pairs_of_branches ? 2 : 1;
      if (list.size() < 2 * fewest) {
        problem(lp, std::to_string(list.size() / 2) + " samples: expected at least " + std::to_string(fewest));
        ok = false;
        continue;
      }
      FabBranchCurve c;
      c.cycle = static_cast<int>(b / 2) + 1;
      c.branch = b % 2 == 0 ? FabBranch::loading : FabBranch::relaxation;
      for (std::size_t k = 0; k < list.size(); k += 2) {
        const json& d = list[k];
        const json& f = list[k + 1];
        bool good = true;
        for (const auto& [v, i] : {std::pair<const json&, std::size_t>{d, k}, {f, k + 1}}) {
          if (!v.is_number()) {
            problem(lp + "/" + std::to_string(i), "expected a number, got " + describe(v));
            good = false;
          } else if (!std::isfinite(v.get<double>())) {
            problem(lp + "/" + std::to_string(i), "not a finite number");
            good = false;
          }
        }
        // The thickness test presses the strip past contact: its distances may reach below zero.
        if (good && pairs_of_branches && d.get<double>() <= 0.0) {
          problem(lp + "/" + std::to_string(k), "clamp distance must be positive, got " + format_g(d.get<double>()) + " cm");
          good = false;
        }
        if (!good) {
          ok = false;
          if (++m_sample_problems > 20) return {};  // enough to show what is wrong
          continue;
        }
        c.clamp_distance.push_back(d.get<double>() * k_cm);
        c.raw_force.push_back(f.get<double>() * k_gram_force);
      }
      out.push_back(std::move(c));
    }
    if (!ok) out.clear();
    return out;
  }

 private:
  std::string m_label;
  Problems& m_problems;
  int m_sample_problems = 0;
};

std::optional<FabTest> read_test(RawReader& r, const json& grain, const FabTestName& spec, const std::string& path,
                                 FabMeasurement& m) {
  const json* t = r.object(grain, spec.name, path, "a test of the protocol");
  if (!t) return std::nullopt;
  const std::string p = path + "/" + spec.name;
  FabTest test;
  test.name = spec.name;
  test.kind = spec.kind;
  const auto length = r.number(*t, "length", p, true);
  const auto width = r.number(*t, "width", p, true);
  const auto freq = r.integer(*t, "freq", p, true);
  if (freq && (*freq <= 0 || *freq > 1'000'000))
    r.problem(p + "/freq", "a sampling rate of 1 to 1,000,000 Hz expected, got " + std::to_string(*freq));
  const auto serial = r.integer(*t, "hwSerialNumber", p, true);
  const auto hw = r.integer(*t, "hwVersion", p, true);
  test.test_version = r.integer(*t, "testVersion", p, true);
  test.time = r.integer(*t, "time", p, true);
  // Seconds since 1970: from then to 2100.
  if (test.time && (*test.time < 0 || *test.time > 4'102'444'800LL)) {
    r.problem(p + "/time", "a time between 1970 and 2100 (seconds since 1970) expected, got " + std::to_string(*test.time));
    test.time.reset();
  }
  test.branches = r.branches(*t, p, true);
  if (!length || !width || test.branches.empty()) return std::nullopt;
  // The protocol's clamp distances are 2 and 8 cm; a length far from its test's is a mislabel.
  if (*length * k_cm < 0.5 * spec.nominal_distance || *length * k_cm > 2.0 * spec.nominal_distance)
    r.problem(p + "/length", format_g(*length) + " cm is not a clamp distance of a " + spec.name + " test (" +
                                 format_g(spec.nominal_distance / k_cm) + " cm)");
  test.clamp_distance = *length * k_cm;
  test.strip_width = *width * k_cm;
  if (freq && *freq > 0 && *freq <= 1'000'000) test.sampling_hz = static_cast<int>(*freq);
  if (serial && !m.serial) m.serial = serial;
  if (hw && !m.hardware_version) m.hardware_version = hw;
  if (const auto z = estimate_zero_offset(test)) {
    test.zero_offset = z->value;
    test.zero_offset_samples = z->samples;
  }
  return test;
}

// A custom-block value that vendors write as a number or as text.
std::string custom_text(const json& block, const char* key) {
  const auto it = block.find(key);
  if (it == block.end()) return "";
  if (it->is_string()) return it->get<std::string>();
  if (it->is_number()) return format_g(it->get<double>());
  return "";
}

void read_custom(const json& doc, FabMeasurement& m) {
  const auto c = doc.find("custom");
  if (c == doc.end() || !c->is_object()) return;
  const auto bw = c->find("browzwear");
  if (bw == c->end() || !bw->is_object()) return;
  m.name = custom_text(*bw, "name");
  m.category = custom_text(*bw, "category");
  if (const auto comp = bw->find("composition"); comp != bw->end() && comp->is_array()) {
    std::string text;
    for (const auto& fibre : *comp) {
      if (!fibre.is_object()) continue;
      const std::string name = custom_text(fibre, "fiber_name");
      if (name.empty()) continue;
      std::string share = custom_text(fibre, "percentage");
      std::string why;
      if (const auto v = parse_finite_number(share, why)) share = format_g(*v <= 1.0 ? 100.0 * *v : *v, 3) + " %";
      text += (text.empty() ? "" : ", ") + name + (share.empty() ? "" : " " + share);
    }
    m.composition = text;
  }
}

}  // namespace

std::optional<Direction> fab_grain_direction(char grain) {
  switch (grain) {
    case 'L': return Direction::warp;
    case 'W': return Direction::weft;
    case 'B': return Direction::bias;
    default: return std::nullopt;
  }
}

char fab_grain_letter(Direction d) {
  switch (d) {
    case Direction::warp: return 'L';
    case Direction::weft: return 'W';
    case Direction::bias: return 'B';
  }
  return '?';
}

std::optional<ZeroOffset> estimate_zero_offset(const FabTest& test) {
  if (test.kind != FabTestKind::stretch) return std::nullopt;
  std::vector<double> slack;
  for (const auto& b : test.branches)
    for (std::size_t i = 0; i < b.clamp_distance.size(); ++i)
      if (b.clamp_distance[i] <= (1.0 - k_slack_fraction) * test.clamp_distance) slack.push_back(b.raw_force[i]);
  if (slack.size() < 3) return std::nullopt;
  const auto mid = slack.begin() + static_cast<std::ptrdiff_t>(slack.size() / 2);
  std::nth_element(slack.begin(), mid, slack.end());
  double median = *mid;
  if (slack.size() % 2 == 0) median = 0.5 * (median + *std::max_element(slack.begin(), mid));
  return ZeroOffset{median, static_cast<int>(slack.size())};
}

FabRead parse_fab_physics(std::string_view text, const std::string& label) {
  FabRead out;
  Problems& problems = out.problems;
  const auto doc = parse_json(text, label, problems);
  if (!doc) return out;
  if (!doc->is_object()) {
    problems.add(label, 0, "/", "expected a U3M physics object (schema, raw_data, custom), got " + describe(*doc));
    return out;
  }
  if (const auto s = doc->find("schema"); s != doc->end() && !(s->is_string() && s->get<std::string>() == "1.1"))
    problems.add(label, 0, "/schema", "expected \"1.1\" (U3M 1.1 physics), got " + describe(*s));
  const auto raw = doc->find("raw_data");
  if (raw == doc->end() || raw->is_null()) {
    problems.add(label, 0, "/raw_data",
                 raw == doc->end() ? "missing: this is not a U3M physics file with FAB measurements"
                                   : "null: the file holds no FAB measurement (a fitted model only?)");
    return out;
  }
  if (!raw->is_object()) {
    problems.add(label, 0, "/raw_data", "expected an object of FAB measurements, got " + describe(*raw));
    return out;
  }
  FabMeasurement m;
  m.label = label;
  RawReader r(label, problems);
  for (const char grain : {'L', 'W', 'B'}) {
    const std::string gp = std::string("/raw_data/") + grain;
    const json* g = r.object(*raw, std::string(1, grain), "/raw_data",
                             grain == 'L' ? "the length grain's tests" : grain == 'W' ? "the width grain's tests" : "the bias grain's tests");
    if (!g) continue;
    auto& tests = m.tests[*fab_grain_direction(grain)];
    for (const auto& spec : k_fab_tests)
      if (auto t = read_test(r, *g, spec, gp, m)) tests.push_back(std::move(*t));
  }
  if (const auto mass = r.number(*raw, "M", "/raw_data", true)) m.mass_per_area = *mass * k_gsm;
  if (const json* t = r.object(*raw, "T", "/raw_data", "the thickness test")) {
    const auto branches = r.branches(*t, "/raw_data/T", false);
    // The FAB's own thickness figure is the first contact distance of the first approach.
    if (!branches.empty()) m.thickness = branches.front().clamp_distance.front();
  }
  if (const auto b = raw->find("Build"); b != raw->end() && b->is_number_integer()) m.build = b->get<long long>();
  read_custom(*doc, m);
  m.physics_text = std::string(text);
  if (problems.empty()) out.measurement = std::move(m);
  return out;
}

namespace {

using ArchivePtr = std::unique_ptr<archive, int (*)(archive*)>;

// The entries of a .u3ma (a zip) by name, each within the size limit.
std::optional<std::map<std::string, std::string>> read_u3ma(const std::string& bytes, const std::string& label,
                                                              Problems& problems) {
  ArchivePtr a(archive_read_new(), archive_read_free);
  archive_read_support_format_zip_seekable(a.get());
  archive_read_support_filter_none(a.get());
  if (archive_read_open_memory(a.get(), bytes.data(), bytes.size()) != ARCHIVE_OK) {
    problems.add(label, 0, "file", std::string("not a .u3ma (zip) archive: ") + archive_error_string(a.get()));
    return std::nullopt;
  }
  std::map<std::string, std::string> files;
  archive_entry* e = nullptr;
  std::uintmax_t total = 0;
  while (true) {
    const int rc = archive_read_next_header(a.get(), &e);
    if (rc == ARCHIVE_EOF) break;
    if (rc != ARCHIVE_OK) {
      problems.add(label, 0, "file", std::string("unreadable archive: ") + archive_error_string(a.get()));
      return std::nullopt;
    }
    if (archive_entry_filetype(e) != AE_IFREG) continue;
    const char* name = archive_entry_pathname_utf8(e);
    if (!name) name = archive_entry_pathname(e);
    std::string data;
    char buffer[65536];
    la_ssize_t n = 0;
    while ((n = archive_read_data(a.get(), buffer, sizeof buffer)) > 0) {
      data.append(buffer, static_cast<std::size_t>(n));
      total += static_cast<std::uintmax_t>(n);
      if (total > k_max_file_bytes) {
        problems.add(label, 0, "file", "unpacks to more than " + std::to_string(k_max_file_bytes >> 20) + " MiB");
        return std::nullopt;
      }
    }
    if (n < 0) {
      problems.add(label, 0, name ? name : "file", std::string("unreadable entry: ") + archive_error_string(a.get()));
      return std::nullopt;
    }
    files[name ? name : ""] = std::move(data);
  }
  return files;
}

// The physics file a .u3m material names (material.physics.devices.fab), or a problem.
std::optional<std::string> named_physics(const std::string& text, const std::string& label, Problems& problems) {
  const auto doc = parse_json(text, label, problems);
  if (!doc) return std::nullopt;
  const json* at = &*doc;
  std::string path;
  for (const char* key : {"material", "physics", "devices", "fab"}) {
    path += std::string("/") + key;
    if (!at->is_object() || !at->contains(key) || (*at)[key].is_null()) {
      problems.add(label, 0, path, "missing: a .u3m names its FAB physics file at /material/physics/devices/fab");
      return std::nullopt;
    }
    at = &(*at)[key];
  }
  if (!at->is_string() || at->get<std::string>().empty()) {
    problems.add(label, 0, path, "expected a relative file name, got " + describe(*at));
    return std::nullopt;
  }
  return at->get<std::string>();
}

}  // namespace

FabRead read_fab_file(const fs::path& file) {
  FabRead out;
  const std::string label = file.string();
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {  // not a folder, a FIFO or a device read without end
    out.problems.add(label, 0, "file", fs::exists(file, ec) ? "not a regular file" : "no such file");
    return out;
  }
  if (const auto size = fs::file_size(file, ec); !ec && size > k_max_file_bytes) {
    out.problems.add(label, 0, "file", "larger than " + std::to_string(k_max_file_bytes >> 20) + " MiB");
    return out;
  }
  std::string text, why;
  if (!read_text_file(file, text, why)) {
    out.problems.add(label, 0, "file", why);
    return out;
  }
  const std::string ext = file.extension().string();
  if (ext == ".u3ma") {
    const auto files = read_u3ma(text, label, out.problems);
    if (!files) return out;
    std::vector<std::string> materials;
    for (const auto& [name, data] : *files)
      if (name.size() > 4 && name.substr(name.size() - 4) == ".u3m" && name.find('/') == std::string::npos)
        materials.push_back(name);
    if (materials.size() != 1) {
      out.problems.add(label, 0, "file", std::to_string(materials.size()) +
                                             " .u3m materials at the archive's top: expected exactly one");
      return out;
    }
    const std::string mlabel = label + "!" + materials.front();
    const auto physics = named_physics(files->at(materials.front()), mlabel, out.problems);
    if (!physics) return out;
    const fs::path wanted = fs::path(*physics).lexically_normal();
    auto it = files->end();
    if (wanted.is_relative() && !wanted.empty() && *wanted.begin() != "..")
      for (auto f = files->begin(); f != files->end(); ++f)
        if (fs::path(f->first).lexically_normal() == wanted) it = f;
    if (it == files->end()) {
      out.problems.add(mlabel, 0, "/material/physics/devices/fab", "'" + *physics + "' is not a file of the archive");
      return out;
    }
    return parse_fab_physics(it->second, label + "!" + it->first);
  }
  if (ext == ".u3m") {
    const auto physics = named_physics(text, label, out.problems);
    if (!physics) return out;
    std::string inside_why;
    const fs::path p = file_inside_folder(file.parent_path().empty() ? fs::path(".") : file.parent_path(), *physics, inside_why);
    if (p.empty()) {
      out.problems.add(label, 0, "/material/physics/devices/fab", inside_why);
      return out;
    }
    // The named file is the physics itself (never another material: no chains, no loops).
    std::string physics_text;
    if (!fs::is_regular_file(p, ec) || !read_text_file(p, physics_text, why)) {
      out.problems.add(p.string(), 0, "file", why.empty() ? "not a regular file" : why);
      return out;
    }
    return parse_fab_physics(physics_text, p.string());
  }
  return parse_fab_physics(text, label);
}

}  // namespace yarnfit::db
