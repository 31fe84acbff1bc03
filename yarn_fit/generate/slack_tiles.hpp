#pragma once
// The slack reproducers (issue 37): tiles whose yarns are slack at rest and at small stretch,
// so that the energy is nearly flat along whole families of motions (yarns sliding or
// drifting between contacts). Each is built from a documented construction at two yarn radii:
//   plain_R…    plain weave, yarns 1.5 mm apart (woven_tile.hpp)
//   basket_R…   2 × 2 basket weave, yarns 1.5 mm apart
//   loose_st_R… stockinette knitted loosely: stitch length 11.28 mm (the acrylic knits'),
//               thin yarn (tile make's generator, knit_generation.hpp)
//   open_rib_R… 1 × 1 rib at the same stitch length: knit and purl wales separate into an
//               open structure whose loops meet in few contacts (the nearest open-work knit
//               a chart of knits and purls can make; lace with yarn-overs needs a chart
//               tile make does not have)
// with the default parameters for the radius (SPEC §3, ks2 = 400 N). The woven tiles are the
// geometry as constructed; the knit tiles come relaxed from the generator. The tests and
// bench_yarn_fit run the rest-shape heuristic on each before they sweep it.

#include <string>
#include <vector>

#include "fabrics_db/tile/periodic_tile.hpp"
#include "yarn_fit/model/yarn_params.hpp"

namespace yarnfit::yarn {

struct SlackReproducer {
  std::string name;
  std::string construction;  // in words, with the figures
  db::PeriodicTile tile;
  YarnParams params;
};

// The reproducers' names, woven first.
[[nodiscard]] const std::vector<std::string>& slack_reproducer_names();

// Builds one reproducer. Throws an input Error for an unknown name and
// an Error when the knit generator does not relax the tile.
SlackReproducer make_slack_reproducer(const std::string& name);

}  // namespace yarnfit::yarn
