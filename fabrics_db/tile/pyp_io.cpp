// Reading and writing periodic yarn tiles in the HYLC "pyp" layout (SPEC §6).
//
// The reader works in two passes: first it splits the text into sections and rows (so that
// row counts, duplicates and unknown sections are known before any value is used), then it
// parses and cross-checks the values. Every problem is recorded and the reader carries on,
// so a user fixing a file sees all of its problems at once.
#include "fabrics_db/tile/periodic_tile.hpp"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string_view>

#include "fabrics_db/text_util.hpp"
#include "numerics/util/error.hpp"

namespace yarnfit::db {
namespace {

// One section of the format: its name after '*', the names of its columns (used as the
// field of a problem, e.g. "*E v1"), the comment the writer puts on its header line, and
// whether its values are integers.
struct SectionSpec {
  std::string_view name;
  std::vector<std::string_view> columns;
  std::string_view comment;
  bool required = false;
};

// In file order; the writer emits them in this order too.
const std::vector<SectionSpec>& section_specs() {
  static const std::vector<SectionSpec> specs = {
      {"pattern", {"px", "py", "radius", "n"}, "px py radius num_vertedges", true},
      {"Q", {"x", "y", "z", "t"}, "dofs: x y z t", true},
      {"E", {"v0", "v1", "dx", "dy"}, "edges: v0 v1 dx dy", true},
      {"RL", {""}, "rest lengths", false},
      {"RK", {"k1", "k2"}, "rest kappas", false},
      {"RT", {""}, "rest twists", false},
      {"RefD1", {"x", "y", "z"}, "reference directors", false},
      {"RefT", {""}, "reference twists", false},
  };
  return specs;
}

const SectionSpec* find_spec(std::string_view name) {
  for (const auto& s : section_specs()) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string all_section_names() {
  std::vector<std::string> names;
  for (const auto& s : section_specs()) names.push_back("*" + std::string(s.name));
  return join_words(names, " and ");
}

// Joins pieces into one string. Used instead of "literal" + std::string(...), which GCC 12
// flags with a false -Wrestrict alarm in optimised builds.
std::string cat(std::initializer_list<std::string_view> pieces) {
  std::string out;
  for (const auto piece : pieces) out.append(piece);
  return out;
}

struct Row {
  int line = 0;
  std::vector<std::string_view> tokens;
};

struct Section {
  const SectionSpec* spec = nullptr;
  int header_line = 0;
  std::vector<Row> rows;
};

// Problems of one file, with the file label filled in.
class Reporter {
 public:
  Reporter(std::string file, Problems& problems) : m_file(std::move(file)), m_problems(problems) {}
  void add(int line, const std::string& field, const std::string& message) {
    m_problems.add(m_file, line, field, message);
    ++m_count;
  }
  [[nodiscard]] int count() const { return m_count; }

 private:
  std::string m_file;
  Problems& m_problems;
  int m_count = 0;
};

std::string field_of(const SectionSpec& spec, std::size_t column) {
  if (column < spec.columns.size() && !spec.columns[column].empty()) {
    return cat({"*", spec.name, " ", spec.columns[column]});
  }
  return cat({"*", spec.name});
}

std::string quote(std::string_view token) { return cat({"'", token, "'"}); }

std::optional<double> parse_double(std::string_view token, std::string& why) {
  std::string_view s = token;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) {
    why = "number out of range: " + quote(token);
    return std::nullopt;
  }
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) {
    why = "expected a number, found " + quote(token);
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    why = "expected a finite number, found " + quote(token);
    return std::nullopt;
  }
  return value;
}

std::optional<long long> parse_integer(std::string_view token, std::string& why) {
  std::string_view s = token;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) {
    why = "integer out of range: " + quote(token);
    return std::nullopt;
  }
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) {
    why = "expected an integer, found " + quote(token);
    return std::nullopt;
  }
  return value;
}

// Splits `text` into sections. Lines are 1-based; '\r' before '\n' is dropped (the HYLC
// files have CRLF endings); '#' starts a comment anywhere on a line.
struct SplitResult {
  std::map<std::string_view, Section> sections;  // by name, first occurrence only
  std::string_view last_section;                 // name of the last known section in the file
  int last_line = 0;                             // last line that is not blank
};

SplitResult split_sections(std::string_view text, Reporter& report) {
  SplitResult out;
  Section* current = nullptr;
  bool skipping = false;  // rows of an unknown or duplicate section are ignored
  int line_no = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    out.last_line = line_no;

    if (line.front() == '*') {
      std::string_view rest = line.substr(1);
      const std::size_t name_end = std::min(rest.find_first_of(" \t"), rest.size());
      const std::string_view name = rest.substr(0, name_end);
      const std::string field = "*" + std::string(name);
      if (!trim(rest.substr(name_end)).empty()) {
        report.add(line_no, field,
                   "unexpected text after the section name " + quote(trim(rest.substr(name_end))) +
                       "; values go on the following lines and comments start with '#'");
      }
      const SectionSpec* spec = find_spec(name);
      current = nullptr;
      skipping = true;
      if (spec == nullptr) {
        report.add(line_no, field, "unknown section; expected one of " + all_section_names());
      } else if (const auto it = out.sections.find(spec->name); it != out.sections.end()) {
        report.add(line_no, field,
                   "duplicate section (first on line " + std::to_string(it->second.header_line) +
                       "); each section may appear once");
      } else {
        Section& s = out.sections[spec->name];
        s.spec = spec;
        s.header_line = line_no;
        current = &s;
        skipping = false;
        out.last_section = spec->name;
      }
      continue;
    }

    if (current == nullptr) {
      if (!skipping) {
        report.add(line_no, "file", "values before the first section; a pyp file starts with *pattern");
        skipping = true;  // one problem for the whole run of stray lines
      }
      continue;
    }
    Row row;
    row.line = line_no;
    std::size_t p = 0;
    while (p < line.size()) {
      const std::size_t b = line.find_first_not_of(" \t", p);
      if (b == std::string_view::npos) break;
      const std::size_t e = std::min(line.find_first_of(" \t", b), line.size());
      row.tokens.push_back(line.substr(b, e - b));
      p = e;
    }
    current->rows.push_back(std::move(row));
  }
  return out;
}

// Values of one section after parsing; `ok[i]` is false when row i had any problem.
struct Parsed {
  std::vector<std::vector<double>> values;
  std::vector<bool> ok;
  std::vector<int> lines;
  int header_line = 0;
};

// Checks the row count of `section` against `expected` (when known) and parses its rows.
// Integers are checked for being integers but returned as doubles (they are small).
Parsed parse_section(const Section& section, std::optional<int> expected, std::string_view n_origin,
                     bool is_last_section, int last_line, bool integers, Reporter& report) {
  const SectionSpec& spec = *section.spec;
  const std::string name = "*" + std::string(spec.name);
  Parsed out;
  out.header_line = section.header_line;
  const int found = static_cast<int>(section.rows.size());
  if (expected && found != *expected) {
    const std::string counts = "expected " + std::to_string(*expected) + " row" +
                               (*expected == 1 ? "" : "s") + " (" + std::string(n_origin) +
                               "), found " + std::to_string(found);
    if (found > *expected) {
      report.add(section.rows[static_cast<std::size_t>(*expected)].line, name, counts);
    } else if (is_last_section) {
      report.add(last_line, name,
                 "file ends after " + std::to_string(found) + " of " + std::to_string(*expected) +
                     " rows (truncated file?); " + counts);
    } else {
      report.add(section.header_line, name, counts);
    }
  }
  const std::size_t width = spec.columns.size();
  for (const Row& row : section.rows) {
    std::vector<double> values(width, 0.0);
    bool ok = true;
    if (row.tokens.size() != width) {
      std::string columns;
      for (const auto& c : spec.columns) columns.append(columns.empty() ? "" : " ").append(c);
      report.add(row.line, name,
                 "expected " + std::to_string(width) + " value" + (width == 1 ? "" : "s") +
                     (width > 1 ? " (" + columns + ")" : "") + " on the row, found " +
                     std::to_string(row.tokens.size()));
      ok = false;
    } else {
      for (std::size_t c = 0; c < width; ++c) {
        std::string why;
        if (integers) {
          if (const auto v = parse_integer(row.tokens[c], why)) {
            values[c] = static_cast<double>(*v);
            continue;
          }
        } else if (const auto v = parse_double(row.tokens[c], why)) {
          values[c] = *v;
          continue;
        }
        report.add(row.line, field_of(spec, c), why);
        ok = false;
      }
    }
    out.values.push_back(std::move(values));
    out.ok.push_back(ok);
    out.lines.push_back(row.line);
  }
  return out;
}

using Vec3 = std::array<double, 3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double norm(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Directors must be unit vectors; the HYLC files store them in single precision.
constexpr double k_director_tolerance = 1e-3;
// An edge shorter than this fraction of the larger period is treated as zero-length: its
// tangent, and everything the simulator derives from it, would be undefined.
constexpr double k_zero_length_fraction = 1e-9;
// How far apart, in periods, a tile's vertices may lie along x or along y. HYLC's tiles and
// the generated ones span about one period; a tile spanning thousands (found by fuzzing)
// describes the same yarns far apart, and every contact search would visit the copies in
// between (compute_tile_facts refuses beyond 1e5 copies a pair).
constexpr double k_max_span_periods = 10.0;

}  // namespace

std::array<double, 3> PeriodicTile::edge_end(int e) const {
  assert(e >= 0 && e < edge_count());
  const TileEdge& edge = edges[static_cast<std::size_t>(e)];
  const auto& p = positions[static_cast<std::size_t>(edge.v1)];
  return {p[0] + edge.dx * period_x, p[1] + edge.dy * period_y, p[2]};
}

std::array<double, 3> default_reference_director(const std::array<double, 3>& tangent) {
  const double len = norm(tangent);
  if (!(len > 0.0)) return {1.0, 0.0, 0.0};
  const Vec3 t = {tangent[0] / len, tangent[1] / len, tangent[2] / len};
  Vec3 d = cross(t, {0.0, 0.0, 1.0});
  double dn = norm(d);
  if (dn < 1e-6) {
    // Tangent (nearly) along z: take the part of x perpendicular to it.
    d = {1.0 - t[0] * t[0], -t[0] * t[1], -t[0] * t[2]};
    dn = norm(d);
  }
  return {d[0] / dn, d[1] / dn, d[2] / dn};
}

void fill_tile_defaults(PeriodicTile& tile) {
  const std::size_t nv = tile.positions.size();
  const std::size_t ne = tile.edges.size();
  if (tile.twists.empty()) tile.twists.assign(nv, 0.0);
  if (tile.rest_lengths.empty()) {
    for (int e = 0; e < static_cast<int>(ne); ++e) {
      const auto& edge = tile.edges[static_cast<std::size_t>(e)];
      tile.rest_lengths.push_back(
          norm(sub(tile.edge_end(e), tile.positions[static_cast<std::size_t>(edge.v0)])));
    }
  }
  if (tile.rest_curvatures.empty()) tile.rest_curvatures.assign(nv, {0.0, 0.0});
  if (tile.rest_twists.empty()) tile.rest_twists.assign(nv, 0.0);
  if (tile.reference_directors.empty()) {
    for (int e = 0; e < static_cast<int>(ne); ++e) {
      const auto& edge = tile.edges[static_cast<std::size_t>(e)];
      tile.reference_directors.push_back(default_reference_director(
          sub(tile.edge_end(e), tile.positions[static_cast<std::size_t>(edge.v0)])));
    }
  }
  if (tile.reference_twists.empty()) tile.reference_twists.assign(nv, 0.0);
}

namespace {

// *pattern: px py radius n. The periods and radius go into `tile`; n is the row count of
// every other section.
struct Pattern {
  std::optional<int> n;
  std::string n_origin;  // where n comes from, for the row-count problems
  bool ok = false;       // all four values good
};

// The sections every file must have, each reported once where the file ends.
void report_missing_sections(const SplitResult& split, Reporter& report) {
  for (const auto& spec : section_specs()) {
    if (spec.required && !split.sections.contains(spec.name)) {
      report.add(split.last_line, "*" + std::string(spec.name),
                 "required section *" + std::string(spec.name) + " is missing (file ends at line " +
                     std::to_string(split.last_line) + "; truncated file?)");
    }
  }
}

Pattern read_pattern(const SplitResult& split, PeriodicTile& tile, Reporter& report) {
  Pattern out;
  const auto it = split.sections.find("pattern");
  if (it == split.sections.end()) return out;
  const Section& s = it->second;
  const Parsed p = parse_section(s, 1, "one line: px py radius n", split.last_section == "pattern", split.last_line,
                                 false, report);
  if (p.values.empty() || !p.ok[0]) return out;
  const auto& v = p.values[0];
  const int line = p.lines[0];
  out.ok = true;
  const char* names[] = {"px", "py", "radius"};
  for (int c = 0; c < 3; ++c) {
    if (!(v[static_cast<std::size_t>(c)] > 0.0)) {
      report.add(line, "*pattern " + std::string(names[c]),
                 "must be positive, found " + format_g(v[static_cast<std::size_t>(c)], 17));
      out.ok = false;
    }
  }
  tile.period_x = v[0];
  tile.period_y = v[1];
  tile.radius = v[2];
  // n is read as a number so that "13.0" gets a clear message rather than a parse error.
  const double nv = v[3];
  if (!(nv >= 1.0) || nv != std::floor(nv) || nv > 1e8) {
    report.add(line, "*pattern n",
               "number of vertices and edges must be a positive integer, found " + std::string(s.rows[0].tokens[3]));
    out.ok = false;
  } else {
    out.n = static_cast<int>(nv);
    out.n_origin = "n = " + std::to_string(*out.n) + " in *pattern on line " + std::to_string(line);
  }
  return out;
}

// All sections but *pattern: n rows each (*E of integers).
std::map<std::string_view, Parsed> parse_row_sections(const SplitResult& split, const Pattern& pattern,
                                                      Reporter& report) {
  std::map<std::string_view, Parsed> parsed;
  for (const auto& spec : section_specs()) {
    if (spec.name == "pattern") continue;
    if (const auto it = split.sections.find(spec.name); it != split.sections.end()) {
      parsed[spec.name] = parse_section(it->second, pattern.n, pattern.n_origin, split.last_section == spec.name,
                                        split.last_line, spec.name == "E", report);
    }
  }
  return parsed;
}

// A vertex's second outgoing (or incoming) edge, reported once the edges are all read.
struct RepeatedEnd {
  int line = 0;
  bool outgoing = false;
  std::size_t vertex = 0;
  int first_line = 0;
};

// "; vertices 3 and 7 have no outgoing edge" for the vertices whose line is 0 (none: "").
std::string vertices_without(const std::vector<int>& lines, const char* kind) {
  std::vector<std::string> names;
  for (std::size_t vtx = 0; vtx < lines.size(); ++vtx) {
    if (lines[vtx] == 0) names.push_back(std::to_string(vtx));
  }
  if (names.empty()) return std::string();
  return "; vert" + std::string(names.size() == 1 ? "ex " : "ices ") + join_words(names, " and ") + " ha" +
         (names.size() == 1 ? "s" : "ve") + " no " + kind + " edge";
}

// Whether the indices and offsets of edge row i are in range (each bad one reported).
bool edge_row_in_range(const Parsed& e, std::size_t i, int vertex_count, Reporter& report) {
  const auto& v = e.values[i];
  const int line = e.lines[i];
  bool ok = true;
  for (int c = 0; c < 2; ++c) {
    const double idx = v[static_cast<std::size_t>(c)];
    if (idx < 0 || (vertex_count >= 0 && idx >= vertex_count)) {
      report.add(line, c == 0 ? "*E v0" : "*E v1",
                 "vertex index " + format_g(idx, 17) + " out of range" +
                     (vertex_count > 0 ? " [0, " + std::to_string(vertex_count - 1) + "]" : std::string()));
      ok = false;
    }
  }
  for (int c = 2; c < 4; ++c) {
    const double off = v[static_cast<std::size_t>(c)];
    if (off < -1 || off > 1) {
      report.add(line, c == 2 ? "*E dx" : "*E dy", "period offset " + format_g(off, 17) + " outside {-1, 0, 1}");
      ok = false;
    }
  }
  return ok;
}

// Edges: indices, offsets, one outgoing and one incoming edge per vertex. Returns which rows
// are good edges (for the zero-length check).
std::vector<bool> check_edge_ends(const Parsed& e, int vertex_count, Reporter& report) {
  std::vector<int> out_line(vertex_count > 0 ? static_cast<std::size_t>(vertex_count) : 0, 0);
  std::vector<int> in_line(out_line.size(), 0);
  std::vector<bool> edge_ok = e.ok;
  std::vector<RepeatedEnd> repeats;
  for (std::size_t i = 0; i < e.values.size(); ++i) {
    if (!e.ok[i]) continue;
    if (!edge_row_in_range(e, i, vertex_count, report)) edge_ok[i] = false;
    if (!edge_ok[i] || vertex_count < 0) continue;
    const int line = e.lines[i];
    const auto v0 = static_cast<std::size_t>(e.values[i][0]);
    const auto v1 = static_cast<std::size_t>(e.values[i][1]);
    // A vertex with a second outgoing (incoming) edge is reported on the line of that
    // edge; which vertex is left without one is only known at the end.
    if (out_line[v0] != 0) {
      repeats.push_back({line, true, v0, out_line[v0]});
      edge_ok[i] = false;
    } else {
      out_line[v0] = line;
    }
    if (in_line[v1] != 0) {
      repeats.push_back({line, false, v1, in_line[v1]});
      edge_ok[i] = false;
    } else {
      in_line[v1] = line;
    }
  }
  // With as many edges as vertices, every vertex without an edge goes with another vertex's
  // second one, so reporting the second edges (naming the vertices left without) gives one
  // problem per mistake. Vertices left without an edge because of a bad row or a missing
  // row were already reported there.
  for (const RepeatedEnd& r : repeats) {
    const char* kind = r.outgoing ? "outgoing" : "incoming";
    report.add(r.line, r.outgoing ? "*E v0" : "*E v1",
               "vertex " + std::to_string(r.vertex) + " has a second " + kind + " edge (the first is on line " +
                   std::to_string(r.first_line) + ")" + vertices_without(r.outgoing ? out_line : in_line, kind) +
                   "; every vertex needs exactly one outgoing and one incoming edge, so that "
                   "yarns are closed periodic loops");
  }
  return edge_ok;
}

void report_zero_length_edges(const Parsed& e, const std::vector<bool>& edge_ok, const Parsed& q,
                              const PeriodicTile& tile, Reporter& report) {
  const double tol = k_zero_length_fraction * std::max(tile.period_x, tile.period_y);
  for (std::size_t i = 0; i < e.values.size(); ++i) {
    if (!edge_ok[i]) continue;
    const auto& v = e.values[i];
    const auto v0 = static_cast<std::size_t>(v[0]);
    const auto v1 = static_cast<std::size_t>(v[1]);
    if (v0 >= q.values.size() || v1 >= q.values.size() || !q.ok[v0] || !q.ok[v1]) continue;
    const Vec3 a = {q.values[v0][0], q.values[v0][1], q.values[v0][2]};
    const Vec3 b = {q.values[v1][0] + v[2] * tile.period_x, q.values[v1][1] + v[3] * tile.period_y,
                    q.values[v1][2]};
    if (norm(sub(b, a)) <= tol) {
      report.add(e.lines[i], "*E",
                 "edge from vertex " + std::to_string(v0) + " to vertex " + std::to_string(v1) + " (offset " +
                     format_g(v[2]) + " " + format_g(v[3]) + ") has zero length; its end points coincide");
    }
  }
}

// Vertices may lie at most k_max_span_periods apart along x and along y. The problem points at
// the extreme vertex farther from the median, the one most likely mistyped.
void report_vertices_spanning_too_far(const Parsed& q, const PeriodicTile& tile, Reporter& report) {
  std::vector<std::size_t> good;
  for (std::size_t i = 0; i < q.values.size(); ++i) {
    if (q.ok[i]) good.push_back(i);
  }
  if (good.size() < 2) return;
  const double periods[] = {tile.period_x, tile.period_y};
  const char* axes[] = {"x", "y"};
  for (std::size_t c = 0; c < 2; ++c) {
    const auto coord = [&](std::size_t i) { return q.values[i][c]; };
    const auto [lo, hi] = std::minmax_element(good.begin(), good.end(),
                                              [&](std::size_t a, std::size_t b) { return coord(a) < coord(b); });
    const double span = (coord(*hi) - coord(*lo)) / periods[c];
    if (!(span > k_max_span_periods)) continue;
    std::vector<double> sorted;
    for (std::size_t i : good) sorted.push_back(coord(i));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const bool hi_is_odd = coord(*hi) - median >= median - coord(*lo);
    const std::size_t odd = hi_is_odd ? *hi : *lo;
    const std::size_t other = hi_is_odd ? *lo : *hi;
    report.add(q.lines[odd], cat({"*Q ", axes[c]}),
               cat({"vertex ", std::to_string(odd), " at ", axes[c], " = ", format_g(coord(odd)), " lies ",
                    format_g(span, 3), " periods from vertex ", std::to_string(other), " at ", axes[c], " = ",
                    format_g(coord(other)), " (line ", std::to_string(q.lines[other]),
                    "); a tile's vertices must lie within ", format_g(k_max_span_periods),
                    " periods of one another along x and along y (HYLC's tiles span about one)"}));
  }
}

// Rest lengths must be positive; directors must be unit vectors.
void check_rest_lengths_and_directors(const std::map<std::string_view, Parsed>& parsed, Reporter& report) {
  if (const auto it = parsed.find("RL"); it != parsed.end()) {
    for (std::size_t i = 0; i < it->second.values.size(); ++i) {
      if (it->second.ok[i] && !(it->second.values[i][0] > 0.0)) {
        report.add(it->second.lines[i], "*RL",
                   "rest length must be positive, found " + format_g(it->second.values[i][0], 17));
      }
    }
  }
  if (const auto it = parsed.find("RefD1"); it != parsed.end()) {
    for (std::size_t i = 0; i < it->second.values.size(); ++i) {
      const auto& v = it->second.values[i];
      const double len = norm({v[0], v[1], v[2]});
      if (it->second.ok[i] && std::abs(len - 1.0) > k_director_tolerance) {
        report.add(it->second.lines[i], "*RefD1",
                   "reference director must be a unit vector, its length is " + format_g(len));
      }
    }
  }
}

// The values of a file without problems (every section present has exactly n good rows);
// sections left out get their documented defaults.
void fill_tile_values(const Parsed& q, const Parsed& e, const std::map<std::string_view, Parsed>& parsed,
                      PeriodicTile& tile) {
  for (const auto& v : q.values) {
    tile.positions.push_back({v[0], v[1], v[2]});
    tile.twists.push_back(v[3]);
  }
  for (const auto& v : e.values) {
    tile.edges.push_back(
        TileEdge{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2]), static_cast<int>(v[3])});
  }
  for (const auto& [name, p] : parsed) {
    for (const auto& v : p.values) {
      if (name == "RL") tile.rest_lengths.push_back(v[0]);
      else if (name == "RK") tile.rest_curvatures.push_back({v[0], v[1]});
      else if (name == "RT") tile.rest_twists.push_back(v[0]);
      else if (name == "RefD1") tile.reference_directors.push_back({v[0], v[1], v[2]});
      else if (name == "RefT") tile.reference_twists.push_back(v[0]);
    }
  }
  fill_tile_defaults(tile);
}

}  // namespace

std::optional<PeriodicTile> parse_pyp(const std::string& text, const std::string& file_label,
                                      Problems& problems) {
  Reporter report(file_label, problems);
  if (trim(text).empty()) {
    report.add(0, "file", "file is empty; expected a pyp tile starting with *pattern");
    return std::nullopt;
  }
  const SplitResult split = split_sections(text, report);
  report_missing_sections(split, report);
  PeriodicTile tile;
  const Pattern pattern = read_pattern(split, tile, report);
  const std::map<std::string_view, Parsed> parsed = parse_row_sections(split, pattern, report);
  const Parsed* q = parsed.contains("Q") ? &parsed.at("Q") : nullptr;
  const Parsed* e = parsed.contains("E") ? &parsed.at("E") : nullptr;
  if (e != nullptr) {
    const int vertex_count = pattern.n ? *pattern.n : (q ? static_cast<int>(q->values.size()) : -1);
    const std::vector<bool> edge_ok = check_edge_ends(*e, vertex_count, report);
    // Zero-length edges need the positions and the periods.
    if (q != nullptr && pattern.ok) report_zero_length_edges(*e, edge_ok, *q, tile, report);
  }
  if (q != nullptr && pattern.ok) report_vertices_spanning_too_far(*q, tile, report);
  check_rest_lengths_and_directors(parsed, report);
  if (report.count() > 0 || q == nullptr || e == nullptr) return std::nullopt;
  fill_tile_values(*q, *e, parsed, tile);
  return tile;
}

std::optional<PeriodicTile> read_pyp(const std::filesystem::path& file, Problems& problems) {
  std::string text;
  std::string why;
  if (!read_text_file(file, text, why)) {
    problems.add(file.string(), 0, "file", why);
    return std::nullopt;
  }
  return parse_pyp(text, file.string(), problems);
}

std::string format_pyp(const PeriodicTile& tile, int significant_digits) {
  if (significant_digits < 1) {
    throw Error(ErrorCategory::input, "format_pyp: significant_digits must be at least 1, got " +
                                std::to_string(significant_digits));
  }
  const std::size_t n = tile.positions.size();
  const auto check = [&](std::size_t size, const char* what) {
    if (size != n) {
      throw Error(ErrorCategory::input, std::string("format_pyp: tile has ") + std::to_string(n) +
                                  " vertices but " + std::to_string(size) + " entries in " + what);
    }
  };
  check(tile.twists.size(), "twists");
  check(tile.edges.size(), "edges (*E)");
  check(tile.rest_lengths.size(), "rest_lengths (*RL)");
  check(tile.rest_curvatures.size(), "rest_curvatures (*RK)");
  check(tile.rest_twists.size(), "rest_twists (*RT)");
  check(tile.reference_directors.size(), "reference_directors (*RefD1)");
  check(tile.reference_twists.size(), "reference_twists (*RefT)");

  std::string out;
  out.reserve(n * 300 + 200);
  const auto g = [&](double v) { return format_g(v, significant_digits); };
  const auto header = [&](std::string_view name) {
    for (const auto& spec : section_specs()) {
      if (spec.name == name) out.append(cat({"*", name, " # ", spec.comment, "\n"}));
    }
  };
  header("pattern");
  out += g(tile.period_x) + " " + g(tile.period_y) + " " + g(tile.radius) + " " +
         std::to_string(n) + "\n\n";
  header("Q");
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = tile.positions[i];
    out += g(p[0]) + " " + g(p[1]) + " " + g(p[2]) + " " + g(tile.twists[i]) + "\n";
  }
  out += "\n";
  header("E");
  for (const auto& e : tile.edges) {
    out += std::to_string(e.v0) + " " + std::to_string(e.v1) + " " + std::to_string(e.dx) + " " +
           std::to_string(e.dy) + "\n";
  }
  out += "\n";
  header("RL");
  for (double v : tile.rest_lengths) out += g(v) + "\n";
  out += "\n";
  header("RK");
  for (const auto& k : tile.rest_curvatures) out += g(k[0]) + " " + g(k[1]) + "\n";
  out += "\n";
  header("RT");
  for (double v : tile.rest_twists) out += g(v) + "\n";
  out += "\n";
  header("RefD1");
  for (const auto& d : tile.reference_directors) out += g(d[0]) + " " + g(d[1]) + " " + g(d[2]) + "\n";
  out += "\n";
  header("RefT");
  for (double v : tile.reference_twists) out += g(v) + "\n";
  out += "\n";
  return out;
}

void write_pyp(const PeriodicTile& tile, const std::filesystem::path& file, int significant_digits) {
  write_text_file_atomically(file, format_pyp(tile, significant_digits));
}

}  // namespace yarnfit::db
