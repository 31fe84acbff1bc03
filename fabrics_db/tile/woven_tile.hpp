#pragma once
// The initial geometry of a periodic woven tile from its weave chart, yarn spacing and yarn
// radius (issue 37: slack reproducers; `yarnfit tile make --weave`).
//
// A weave chart says, at every crossing of a weft yarn (running along x) and a warp yarn
// (running along y), which of the two lies on top. Text form: rows separated by '/', row j
// the weft yarn j (the lowest first), each row's crossings from left to right, '1' where the
// warp is on top and '0' where the weft is (spaces ignored). The chart repeats in both
// directions. Named charts:
//   plain      10/01                 every crossing alternates
//   basket2x2  1100/1100/0011/0011   pairs of yarns woven as one (the "hopsack")
//   twill2x2   1100/0110/0011/1001   the floats step one yarn per row
//
// Geometry: yarns of radius R, neighbouring parallel yarns `yarn_spacing` s apart, so the
// period is (warps · s) × (wefts · s). At a crossing the two centrelines are 2·depth·R apart
// in z (depth 1: just touching), shared between the two yarns' crimp by weft_crimp_share. Between two crossings of
// a yarn the depth follows a half cosine, so a float (two crossings on the same side) stays
// flat. Every yarn has `vertices_per_crossing` polyline vertices per crossing, one of them
// over the crossing's centre; rest lengths are the edge lengths, rest curvatures zero (a
// straight yarn at rest), reference directors default, as in the knit tiles. With s well
// above 2R the yarns touch only at the crossings: a slack tile, whose energy is nearly flat
// along yarns sliding and drifting between contacts.

#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/problems.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::db {

struct WeaveChart {
  std::string name;                     // the named chart, or the text as given
  std::vector<std::vector<bool>> rows;  // rows[j][i]: at weft j, warp i, the warp is on top

  [[nodiscard]] int wefts() const { return static_cast<int>(rows.size()); }
  [[nodiscard]] int warps() const { return rows.empty() ? 0 : static_cast<int>(rows.front().size()); }
  // Whether the warp is on top where weft j crosses warp i, both taken periodically.
  [[nodiscard]] bool warp_on_top(int weft, int warp) const;
  // "10/01"-style text of the rows.
  [[nodiscard]] std::string text() const;
};

// The named weave charts, in the order listed above.
[[nodiscard]] const std::vector<std::string>& named_weave_charts();

// A named chart or chart text. Empty with `why` set when the text is empty, holds a character
// other than 0, 1, '/' or spaces, has an empty row or rows of different lengths, or leaves a
// yarn without any crossing on each side (it would not be held in the cloth).
std::optional<WeaveChart> parse_weave_chart(const std::string& text, std::string* why = nullptr);

struct WovenTileOptions {
  double yarn_spacing = 0.0;  // s: centre distance of neighbouring parallel yarns [m]
  double yarn_radius = 0.0;   // R [m]
  int vertices_per_crossing = 6;
  double depth = 1.0;         // half the centreline gap at a crossing, in yarn radii
  // The weft's share of that gap as crimp (Peirce's h_weft / (h_weft + h_warp)): the weft's
  // centreline swings ±2·share·depth·R, the warp's ±2·(1 − share)·depth·R.
  double weft_crimp_share = 0.6;

  // What is wrong, under each option's name; empty if usable.
  [[nodiscard]] Problems problems() const;
};

// The tile, yarns in the order: the wefts (lowest first), then the warps (left first).
// Throws an input Error for bad options or an empty chart.
PeriodicTile make_woven_tile(const WeaveChart& chart, const WovenTileOptions& options);

}  // namespace yarnfit::db
