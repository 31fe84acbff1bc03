// Reading and writing pyp tiles: round trips on real and synthetic tiles, and one broken
// input per rejection rule, each checked for the file, line and field it names.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "fabrics_db/tile/synthetic_stockinette.hpp"
#include "tests/test_support.hpp"
#include "tests/expect_error.hpp"

namespace yarnfit::db {
namespace {

namespace fs = std::filesystem;
using namespace yarnfit::testing;

const char* const k_label = "tile.pyp";

// A small valid tile with every section; the comments give the 1-based line numbers that the
// tests below refer to.
std::vector<std::string> valid_lines() {
  return {
      "*pattern # px py radius num_vertedges",  // 1
      "0.004 0.002 0.0005 4",                   // 2
      "",                                       // 3
      "*Q # dofs: x y z t",                     // 4
      "0 0 0 0",                                // 5  vertex 0
      "0.001 0.0005 0.0002 0.1",                // 6  vertex 1
      "0.002 0 0 0",                            // 7  vertex 2
      "0.003 -0.0005 -0.0002 -0.1",             // 8  vertex 3
      "",                                       // 9
      "*E # edges: v0 v1 dx dy",                // 10
      "0 1 0 0",                                // 11
      "1 2 0 0",                                // 12
      "2 3 0 0",                                // 13
      "3 0 1 0",                                // 14
      "",                                       // 15
      "*RL # rest lengths",                     // 16
      "0.0011",                                 // 17
      "0.0011",                                 // 18
      "0.0011",                                 // 19
      "0.0011",                                 // 20
      "",                                       // 21
      "*RK # rest kappas",                      // 22
      "0 0",                                    // 23
      "0.5 -0.25",                              // 24
      "0 0",                                    // 25
      "-0.5 0.25",                              // 26
      "",                                       // 27
      "*RT # rest twists",                      // 28
      "0",                                      // 29
      "0.01",                                   // 30
      "0",                                      // 31
      "-0.01",                                  // 32
      "",                                       // 33
      "*RefD1 # reference directors",           // 34
      "0 0 1",                                  // 35
      "0 0 1",                                  // 36
      "0 1 0",                                  // 37
      "0 0 1",                                  // 38
      "",                                       // 39
      "*RefT # reference twists",               // 40
      "0",                                      // 41
      "0",                                      // 42
      "0",                                      // 43
      "0",                                      // 44
      "",                                       // 45
  };
}

std::string join(const std::vector<std::string>& lines, const std::string& eol = "\n") {
  std::string out;
  for (const auto& l : lines) out += l + eol;
  return out;
}

// Lines 1..last of `lines`.
std::vector<std::string> head(std::vector<std::string> lines, int last) {
  lines.resize(static_cast<std::size_t>(last));
  return lines;
}

Problems problems_of(const std::string& text) {
  Problems problems;
  const auto tile = parse_pyp(text, k_label, problems);
  EXPECT_EQ(tile.has_value(), problems.empty()) << "a tile must come back exactly when nothing is wrong";
  return problems;
}

// `problem` is at `line` of tile.pyp, names `field`, and its message contains `words`.
void expect_problem(const Problem& problem, int line, const std::string& field, const std::string& words) {
  EXPECT_EQ(problem.file, k_label);
  EXPECT_EQ(problem.line, line) << problem.to_string();
  EXPECT_EQ(problem.field, field) << problem.to_string();
  EXPECT_NE(problem.message.find(words), std::string::npos)
      << "message should contain \"" << words << "\": " << problem.to_string();
  // Problems without a line render as "file: field: message".
  const std::string prefix = std::string(k_label) + (line > 0 ? ":" + std::to_string(line) : "") + ": " +
                             field + ": ";
  EXPECT_EQ(problem.to_string().rfind(prefix, 0), 0u) << problem.to_string();
}

void expect_single_problem(const Problems& problems, int line, const std::string& field,
                           const std::string& words) {
  ASSERT_EQ(problems.size(), 1u) << problems.to_string();
  expect_problem(problems.items()[0], line, field, words);
}

// Every value of `b` equals that of `a` within relative `tolerance` (0: exactly).
void expect_tiles_match(const PeriodicTile& a, const PeriodicTile& b, double tolerance) {
  const auto near = [&](double x, double y, const std::string& what) {
    if (tolerance == 0.0) {
      EXPECT_EQ(x, y) << what;
    } else {
      EXPECT_LE(std::abs(x - y), tolerance * std::abs(x)) << what << ": " << x << " vs " << y;
    }
  };
  near(a.period_x, b.period_x, "px");
  near(a.period_y, b.period_y, "py");
  near(a.radius, b.radius, "radius");
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  ASSERT_EQ(a.edge_count(), b.edge_count());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    const std::string at = " of vertex/edge " + std::to_string(i);
    for (std::size_t c = 0; c < 3; ++c) {
      near(a.positions[i][c], b.positions[i][c], "*Q" + at);
      near(a.reference_directors[i][c], b.reference_directors[i][c], "*RefD1" + at);
    }
    near(a.twists[i], b.twists[i], "*Q t" + at);
    EXPECT_EQ(a.edges[i].v0, b.edges[i].v0);
    EXPECT_EQ(a.edges[i].v1, b.edges[i].v1);
    EXPECT_EQ(a.edges[i].dx, b.edges[i].dx);
    EXPECT_EQ(a.edges[i].dy, b.edges[i].dy);
    near(a.rest_lengths[i], b.rest_lengths[i], "*RL" + at);
    near(a.rest_curvatures[i][0], b.rest_curvatures[i][0], "*RK" + at);
    near(a.rest_curvatures[i][1], b.rest_curvatures[i][1], "*RK" + at);
    near(a.rest_twists[i], b.rest_twists[i], "*RT" + at);
    near(a.reference_twists[i], b.reference_twists[i], "*RefT" + at);
  }
}


// ---------------------------------------------------------------------------------------------
// The valid text, its layout and the defaults of optional sections.

TEST(PypReader, ReadsTheSmallValidTile) {
  Problems problems;
  const auto tile = parse_pyp(join(valid_lines()), k_label, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  EXPECT_EQ(tile->period_x, 0.004);
  EXPECT_EQ(tile->radius, 0.0005);
  ASSERT_EQ(tile->vertex_count(), 4);
  EXPECT_EQ(tile->positions[3][1], -0.0005);
  EXPECT_EQ(tile->twists[1], 0.1);
  EXPECT_EQ(tile->edges[3].v0, 3);
  EXPECT_EQ(tile->edges[3].dx, 1);
  EXPECT_EQ(tile->rest_curvatures[1][1], -0.25);
  EXPECT_EQ(tile->rest_twists[3], -0.01);
  EXPECT_EQ(tile->reference_directors[2][1], 1.0);
  // The last edge closes the yarn through the next tile in x.
  const auto end = tile->edge_end(3);
  EXPECT_DOUBLE_EQ(end[0], 0.004);
  EXPECT_DOUBLE_EQ(end[1], 0.0);
}

TEST(PypReader, AcceptsCrlfLineEndingsLikeTheHylcFiles) {
  Problems lf_problems;
  Problems crlf_problems;
  const auto lf = parse_pyp(join(valid_lines()), k_label, lf_problems);
  const auto crlf = parse_pyp(join(valid_lines(), "\r\n"), k_label, crlf_problems);
  ASSERT_TRUE(lf && crlf) << crlf_problems.to_string();
  expect_tiles_match(*lf, *crlf, 0.0);

  auto lines = valid_lines();
  lines[12 - 1] = "1 9 0 0";
  expect_single_problem(problems_of(join(lines, "\r\n")), 12, "*E v1", "out of range");
}

TEST(PypReader, FillsDocumentedDefaultsForOptionalSections) {
  Problems problems;
  const auto tile = parse_pyp(join(head(valid_lines(), 15)), k_label, problems);
  ASSERT_TRUE(tile) << problems.to_string();
  for (int e = 0; e < tile->edge_count(); ++e) {
    const auto& p = tile->positions[static_cast<std::size_t>(tile->edges[static_cast<std::size_t>(e)].v0)];
    const auto q = tile->edge_end(e);
    const double t[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    const double length = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    EXPECT_DOUBLE_EQ(tile->rest_lengths[static_cast<std::size_t>(e)], length);  // *RL: geometric
    const auto& d = tile->reference_directors[static_cast<std::size_t>(e)];
    EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-14);  // *RefD1: unit ...
    EXPECT_NEAR(d[0] * t[0] + d[1] * t[1] + d[2] * t[2], 0.0, 1e-15);  // ... and perpendicular
  }
  for (std::size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(tile->rest_curvatures[v][0], 0.0);
    EXPECT_EQ(tile->rest_curvatures[v][1], 0.0);
    EXPECT_EQ(tile->rest_twists[v], 0.0);
    EXPECT_EQ(tile->reference_twists[v], 0.0);
  }
}

TEST(PypReader, DefaultDirectorOfAnEdgeAlongZIsPerpendicularToo) {
  const auto d = default_reference_director({0.0, 0.0, 2.0});
  EXPECT_DOUBLE_EQ(d[0], 1.0);
  EXPECT_DOUBLE_EQ(d[1], 0.0);
  EXPECT_DOUBLE_EQ(d[2], 0.0);
  const auto e = default_reference_director({1e-9, 0.0, 1.0});  // nearly along z
  EXPECT_NEAR(e[0] * 1e-9 + e[2], 0.0, 1e-15);
  EXPECT_NEAR(e[0] * e[0] + e[1] * e[1] + e[2] * e[2], 1.0, 1e-14);
}

// ---------------------------------------------------------------------------------------------
// One rule broken per case: replace one line of the valid text and expect exactly one problem.

struct RuleCase {
  const char* name;
  int line;               // line of the valid text to replace
  const char* text;       // its new content
  int problem_line;       // where the problem must point
  const char* field;
  const char* words;      // part of the message
};

class PypRule : public ::testing::TestWithParam<RuleCase> {};

TEST_P(PypRule, OneBrokenLineGivesOneProblemAtItsLineAndField) {
  const RuleCase& c = GetParam();
  auto lines = valid_lines();
  lines[static_cast<std::size_t>(c.line - 1)] = c.text;
  expect_single_problem(problems_of(join(lines)), c.problem_line, c.field, c.words);
}

const RuleCase k_rule_cases[] = {
    {"vertex_index_too_large", 12, "1 9 0 0", 12, "*E v1", "vertex index 9 out of range [0, 3]"},
    {"vertex_index_negative", 11, "-1 1 0 0", 11, "*E v0", "out of range"},
    {"offset_dx_outside", 14, "3 0 2 0", 14, "*E dx", "period offset 2 outside {-1, 0, 1}"},
    {"offset_dy_outside", 13, "2 3 0 -2", 13, "*E dy", "outside {-1, 0, 1}"},
    {"rest_length_zero", 18, "0", 18, "*RL", "rest length must be positive"},
    {"rest_length_negative", 19, "-0.0011", 19, "*RL", "must be positive, found -0.0011"},
    {"too_few_values", 6, "0.001 0.0005 0.0002", 6, "*Q", "expected 4 values (x y z t) on the row, found 3"},
    {"too_many_values", 24, "0.5 -0.25 1", 24, "*RK", "expected 2 values"},
    {"one_value_expected", 30, "0.01 0.02", 30, "*RT", "expected 1 value on the row, found 2"},
    {"text_for_number", 6, "0.001 abc 0.0002 0.1", 6, "*Q y", "expected a number, found 'abc'"},
    {"nan", 7, "0.002 0 nan 0", 7, "*Q z", "expected a finite number, found 'nan'"},
    {"inf", 17, "inf", 17, "*RL", "finite"},
    {"number_with_junk", 42, "0.5mm", 42, "*RefT", "expected a number, found '0.5mm'"},
    {"offset_not_integer", 12, "1 2 0.5 0", 12, "*E dx", "expected an integer, found '0.5'"},
    {"px_zero", 2, "0 0.002 0.0005 4", 2, "*pattern px", "must be positive"},
    {"py_negative", 2, "0.004 -0.002 0.0005 4", 2, "*pattern py", "must be positive"},
    {"radius_zero", 2, "0.004 0.002 0 4", 2, "*pattern radius", "must be positive"},
    {"n_zero", 2, "0.004 0.002 0.0005 0", 2, "*pattern n", "positive integer"},
    {"n_fractional", 2, "0.004 0.002 0.0005 4.5", 2, "*pattern n", "positive integer, found 4.5"},
    {"n_text", 2, "0.004 0.002 0.0005 four", 2, "*pattern n", "expected a number"},
    {"pattern_short_row", 2, "0.004 0.002 0.0005", 2, "*pattern", "expected 4 values"},
    {"unknown_section", 28, "*RX # rest twists", 28, "*RX", "unknown section"},
    {"text_after_section_name", 4, "*Q 1 2", 4, "*Q", "unexpected text after the section name"},
    {"second_outgoing_edge", 13, "1 3 0 0", 13, "*E v0",
     "vertex 1 has a second outgoing edge (the first is on line 12); vertex 2 has no outgoing edge"},
    {"second_incoming_edge", 12, "1 3 0 0", 13, "*E v1",
     "vertex 3 has a second incoming edge (the first is on line 12); vertex 2 has no incoming edge"},
    {"zero_length_edge", 6, "0 0 0 0.1", 11, "*E", "has zero length"},
    {"zero_length_edge_across_period", 8, "0.004 0 0 -0.1", 14, "*E",
     "edge from vertex 3 to vertex 0 (offset 1 0) has zero length"},
    {"vertex_thousands_of_periods_away", 6, "500 0.0005 0.0002 0.1", 6, "*Q x",
     "vertex 1 at x = 500 lies 1.25e+05 periods from vertex 0 at x = 0 (line 5)"},
    {"vertex_far_along_y_reported_at_the_odd_one_out", 7, "0.002 -0.5 0 0", 7, "*Q y", "lies 250 periods"},
    {"director_not_unit", 35, "0 0 2", 35, "*RefD1", "unit vector"},
};

INSTANTIATE_TEST_SUITE_P(Pyp, PypRule, ::testing::ValuesIn(k_rule_cases),
                         [](const ::testing::TestParamInfo<RuleCase>& p) { return std::string(p.param.name); });

// ---------------------------------------------------------------------------------------------
// Rules that need more than one line changed.

TEST(PypReader, SectionWithFewerRowsThanNNamesExpectedAndFound) {
  auto lines = valid_lines();
  lines.erase(lines.begin() + (25 - 1));  // one row of *RK
  expect_single_problem(problems_of(join(lines)), 22, "*RK",
                        "expected 4 rows (n = 4 in *pattern on line 2), found 3");
}

TEST(PypReader, SectionWithMoreRowsThanNPointsAtTheFirstExtraRow) {
  auto lines = valid_lines();
  lines.insert(lines.begin() + 8, "0.0035 0 0 0");  // becomes line 9, a fifth row of *Q
  expect_single_problem(problems_of(join(lines)), 9, "*Q", "expected 4 rows (n = 4 in *pattern on line 2), found 5");
}

TEST(PypReader, HeaderNDisagreeingWithTheSectionsIsReportedForEachSection) {
  auto lines = valid_lines();
  lines[2 - 1] = "0.004 0.002 0.0005 5";
  const Problems problems = problems_of(join(lines));
  ASSERT_EQ(problems.size(), 7u) << problems.to_string();
  expect_problem(problems.items()[0], 4, "*Q", "expected 5 rows (n = 5 in *pattern on line 2), found 4");
  expect_problem(problems.items()[1], 10, "*E", "expected 5 rows");
  // *RefT is last: the file ends before its fifth row.
  expect_problem(problems.items()[6], 44, "*RefT", "file ends after 4 of 5 rows (truncated file?)");
}

TEST(PypReader, TruncatedInsideAnOptionalSection) {
  expect_single_problem(problems_of(join(head(valid_lines(), 30))), 30, "*RT",
                        "file ends after 2 of 4 rows (truncated file?)");
}

TEST(PypReader, TruncatedBeforeARequiredSection) {
  const Problems problems = problems_of(join(head(valid_lines(), 7)));
  ASSERT_EQ(problems.size(), 2u) << problems.to_string();
  expect_problem(problems.items()[0], 7, "*E", "required section *E is missing (file ends at line 7");
  expect_problem(problems.items()[1], 7, "*Q", "file ends after 3 of 4 rows");
}

TEST(PypReader, MissingRequiredSection) {
  auto lines = valid_lines();
  lines.erase(lines.begin() + (10 - 1), lines.begin() + 15);  // *E and its rows
  expect_single_problem(problems_of(join(lines)), 38, "*E", "required section *E is missing");
}

TEST(PypReader, DuplicateSection) {
  auto lines = valid_lines();
  for (const char* l : {"*RL # again", "0.002", "0.002", "0.002", "0.002"}) lines.emplace_back(l);
  expect_single_problem(problems_of(join(lines)), 46, "*RL", "duplicate section (first on line 16)");
}

TEST(PypReader, ValuesBeforeTheFirstSection) {
  auto lines = valid_lines();
  lines.insert(lines.begin(), "1 2 3");
  expect_single_problem(problems_of(join(lines)), 1, "file", "values before the first section");
}

TEST(PypReader, EmptyText) {
  expect_single_problem(problems_of(" \n\n"), 0, "file", "file is empty");
}

TEST(PypReader, EveryProblemIsReportedNotOnlyTheFirst) {
  auto lines = valid_lines();
  lines[2 - 1] = "0.004 0.002 0 4";  // radius
  lines[12 - 1] = "1 9 0 0";         // vertex index
  lines[18 - 1] = "-1";              // rest length
  ScratchDir dir("pyp");
  const fs::path file = dir / "broken.pyp";
  write_file(file, join(lines));
  Problems problems;
  EXPECT_FALSE(read_pyp(file, problems));
  ASSERT_EQ(problems.size(), 3u) << problems.to_string();
  const std::string name = file.string();
  EXPECT_EQ(problems.items()[0].to_string().rfind(name + ":2: *pattern radius: ", 0), 0u)
      << problems.to_string();
  EXPECT_EQ(problems.items()[1].to_string().rfind(name + ":12: *E v1: ", 0), 0u) << problems.to_string();
  EXPECT_EQ(problems.items()[2].to_string().rfind(name + ":18: *RL: ", 0), 0u) << problems.to_string();
}

TEST(PypReader, MissingFileIsOneProblemOnTheFile) {
  ScratchDir dir("pyp");
  const fs::path file = dir / "nowhere.pyp";
  Problems problems;
  EXPECT_FALSE(read_pyp(file, problems));
  ASSERT_EQ(problems.size(), 1u);
  const Problem& p = problems.items()[0];
  EXPECT_EQ(p.file, file.string());
  EXPECT_EQ(p.line, 0);
  EXPECT_EQ(p.field, "file");
  EXPECT_EQ(p.to_string().rfind(file.string() + ": file: ", 0), 0u) << p.to_string();
}

TEST(PypReader, FolderInsteadOfFileIsOneProblemOnTheFile) {
  ScratchDir dir("pyp");
  Problems problems;
  EXPECT_FALSE(read_pyp(dir.path(), problems));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems.items()[0].field, "file");
  EXPECT_EQ(problems.items()[0].line, 0);
}

// ---------------------------------------------------------------------------------------------
// Writing.

void expect_round_trip(const PeriodicTile& tile, int digits, double tolerance) {
  ScratchDir dir("pyp");
  const fs::path file = dir / "tile.pyp";
  write_pyp(tile, file, digits);
  Problems problems;
  const auto back = read_pyp(file, problems);
  ASSERT_TRUE(back) << problems.to_string();
  expect_tiles_match(tile, *back, tolerance);
}

const char* const k_real_tiles[] = {"stocktiniest.pyp", "stocktiny.pyp", "stockinette.pyp",
                                    "cartridge_belt_rib.pyp"};

TEST(PypRoundTrip, RealTilesExactAt17AndWithin1e6At7Digits) {
  for (const char* name : k_real_tiles) {
    SCOPED_TRACE(name);
    const fs::path file = shared_pattern(name);
    YARNFIT_REQUIRE_SHARED(file);
    Problems problems;
    const auto tile = read_pyp(file, problems);
    ASSERT_TRUE(tile) << problems.to_string();
    expect_round_trip(*tile, 17, 0.0);
    expect_round_trip(*tile, 7, 1e-6);
  }
}

TEST(PypRoundTrip, SyntheticTileExactAt17AndWithin1e6At7Digits) {
  const PeriodicTile tile = make_stockinette_tile();
  expect_round_trip(tile, 17, 0.0);
  expect_round_trip(tile, 7, 1e-6);
}

TEST(PypRoundTrip, AwkwardDoublesSurviveAt17Digits) {
  PeriodicTile tile = make_stockinette_tile();
  // Doubles that need all 17 digits, inside the tile (a vertex may not lie more than 10
  // periods from the others).
  tile.positions[0] = {(0.1 + 0.2) * 1e-3, -1e-3 / 3.0, 1e-300};
  tile.positions[1][0] = std::nextafter(tile.positions[1][0], 1.0);
  tile.twists[2] = -0.0;
  tile.rest_curvatures[3] = {1e300, -4.9406564584124654e-320};  // a denormal
  expect_round_trip(tile, 17, 0.0);
}

TEST(PypWriter, ReproducesTheLayoutOfTheRealFiles) {
  // The tiny HYLC tiles were written with 8 significant digits; the writer gives back the
  // same bytes, section order and header comments included.
  for (const char* name : {"stocktiniest.pyp", "stocktiny.pyp"}) {
    SCOPED_TRACE(name);
    const fs::path file = shared_pattern(name);
    YARNFIT_REQUIRE_SHARED(file);
    Problems problems;
    const auto tile = read_pyp(file, problems);
    ASSERT_TRUE(tile) << problems.to_string();
    EXPECT_EQ(format_pyp(*tile, 8), read_file(file));
  }
}

TEST(PypWriter, OverwritesTheGivenPathAndLeavesNoTemporaryFile) {
  ScratchDir dir("pyp");
  const fs::path file = dir / "tile.pyp";
  write_file(file, "old contents\n");
  const PeriodicTile tile = make_stockinette_tile();
  write_pyp(tile, file);
  EXPECT_EQ(read_file(file), format_pyp(tile));
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(PypWriter, ThrowsNamingTheFileWhenItCannotWrite) {
  ScratchDir dir("pyp");
  const fs::path file = dir / "no such folder" / "tile.pyp";
  try {
    write_pyp(make_stockinette_tile(), file);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(PypWriter, RejectsATileWhoseArraysDisagree) {
  PeriodicTile tile = make_stockinette_tile();
  tile.rest_lengths.pop_back();
  EXPECT_ERROR((void)format_pyp(tile), yarnfit::ErrorCategory::input);
  EXPECT_ERROR((void)format_pyp(make_stockinette_tile(), 0), yarnfit::ErrorCategory::input);
}

}  // namespace
}  // namespace yarnfit::db
