#pragma once
// A knitting chart: which stitches of a periodic knit are knits and which are purls, as the
// fabric's face shows them (a knitting chart's right-side view). A knit stitch shows its
// loop's legs on the face (the "V"); a purl shows the head of the loop below it (the bump).
//
// Text form: rows separated by '/', the first row the lowest course (knitted first), each
// row's stitches from left to right as the chart is drawn, 'k' knit and 'p' purl (either
// case; spaces ignored). The chart repeats in both directions, so "kp/pk" is seed stitch,
// "k/p" garter (knit and purl courses alternate on the face), "kp" 1×1 rib. Named charts:
//   stockinette  k          garter  k/p          seed  kp/pk
//   rib1x1       kp         rib2x2  kkpp
// Written knitting instructions describe the same fabrics differently (garter is "knit every
// row" because every other row is worked from the back): the chart here is always the face.

#include <optional>
#include <string>
#include <vector>

namespace yarnfit::db {

enum class Stitch { knit, purl };

struct KnitChart {
  std::string name;                       // the named chart, or the text as given
  std::vector<std::vector<Stitch>> rows;  // rows[j][k]: course j (0 = lowest), wale k

  [[nodiscard]] int courses() const { return static_cast<int>(rows.size()); }
  [[nodiscard]] int wales() const { return rows.empty() ? 0 : static_cast<int>(rows.front().size()); }
  // The stitch at course j, wale k, both taken periodically (any integers).
  [[nodiscard]] Stitch at(int course, int wale) const;
  // +1 for a knit, −1 for a purl at (course, wale), periodically.
  [[nodiscard]] int face_sign(int course, int wale) const { return at(course, wale) == Stitch::knit ? 1 : -1; }
  // "k/p"-style text of the rows.
  [[nodiscard]] std::string text() const;
};

// The named charts, in the order listed above.
[[nodiscard]] const std::vector<std::string>& named_knit_charts();

// A named chart or chart text. Empty with `why` set when the text is empty, holds a character
// other than k, p, '/' or spaces, has an empty row, or rows of different lengths.
std::optional<KnitChart> parse_knit_chart(const std::string& text, std::string* why = nullptr);

}  // namespace yarnfit::db
