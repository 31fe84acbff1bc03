// The HYLC periodic tile (.pyp): parse_pyp lists every problem and gives no tile then.
#include "fabrics_db/tile/periodic_tile.hpp"
#include "fuzz/fuzz_support.hpp"

YARNFIT_FUZZ_TARGET(pyp_tile) {
  using namespace yarnfit;
  db::Problems problems;
  const auto tile = db::parse_pyp(std::string(fuzz::as_text(data, size)), "fuzz.pyp", problems);
  if (tile && !problems.empty()) fuzz::finding("pyp_tile: a result beside problems");
  if (tile) (void)db::compute_tile_facts(*tile);  // what every command does next with a tile
  return 0;
}
