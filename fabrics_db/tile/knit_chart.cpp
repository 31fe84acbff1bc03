#include "fabrics_db/tile/knit_chart.hpp"

#include <array>
#include <cctype>
#include <utility>

#include "fabrics_db/tile/chart_rows.hpp"

namespace yarnfit::db {
namespace {

constexpr std::array<std::pair<const char*, const char*>, 5> kNamed{{{"stockinette", "k"},
                                                                     {"garter", "k/p"},
                                                                     {"rib1x1", "kp"},
                                                                     {"rib2x2", "kkpp"},
                                                                     {"seed", "kp/pk"}}};

int wrap(int i, int n) { return ((i % n) + n) % n; }

}  // namespace

Stitch KnitChart::at(int course, int wale) const {
  const auto& row = rows[static_cast<std::size_t>(wrap(course, courses()))];
  return row[static_cast<std::size_t>(wrap(wale, static_cast<int>(row.size())))];
}

std::string KnitChart::text() const {
  std::string out;
  for (std::size_t j = 0; j < rows.size(); ++j) {
    if (j > 0) out += '/';
    for (const Stitch s : rows[j]) out += s == Stitch::knit ? 'k' : 'p';
  }
  return out;
}

const std::vector<std::string>& named_knit_charts() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& [name, text] : kNamed) v.emplace_back(name);
    return v;
  }();
  return names;
}

std::optional<KnitChart> parse_knit_chart(const std::string& given, std::string* why) {
  const auto fail = [&](std::string message) -> std::optional<KnitChart> {
    if (why != nullptr) *why = std::move(message);
    return std::nullopt;
  };
  std::string text = given;
  for (const auto& [name, chart] : kNamed)
    if (given == name) text = chart;
  std::string lowered;
  for (const char c : text) lowered += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const ChartRows rows = split_chart_rows(lowered, "kp", "chart", given, "stitches");
  if (!rows.problem.empty()) return fail(rows.problem);
  if (rows.unknown_symbol) {
    std::string names;
    for (const auto& n : named_knit_charts()) names += (names.empty() ? "" : ", ") + n;
    return fail("unknown chart '" + given + "': expected one of " + names +
                ", or rows of k (knit) and p (purl) separated by '/', such as kp/pk");
  }
  KnitChart out;
  out.name = given;
  for (const std::string& row : rows.rows) {
    out.rows.emplace_back();
    for (const char c : row) out.rows.back().push_back(c == 'k' ? Stitch::knit : Stitch::purl);
  }
  return out;
}

}  // namespace yarnfit::db
