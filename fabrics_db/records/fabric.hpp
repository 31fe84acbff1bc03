#pragma once
// A fabric record (SPEC §2) in SI units: the folder's fabric.yaml and the curves it names.
//
// Conventions: stretch s = l/l̄ − 1, compression c = 1 − w/w̄ (positive = narrowing), force
// is the total clamp force [N]. With a Gauge, l and w are read between marks placed
// ±length/2 along the pull and ±width/2 across it at mid-length; without one, l is the clamp
// separation and w the free-edge width at mid-length.

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "fabrics_db/records/fab_test.hpp"
#include "fabrics_db/tile/knit_chart.hpp"
#include "fabrics_db/tile/periodic_tile.hpp"

namespace yarnfit::db {

// Test directions relative to the material frame (weft = x).
enum class Direction { weft, bias, warp };
inline constexpr std::array<Direction, 3> k_all_directions{Direction::weft, Direction::bias,
                                                           Direction::warp};
std::string_view to_string(Direction d);
std::optional<Direction> parse_direction(std::string_view name);
// Angle of the pull from the weft axis [rad]: 0, π/4, π/2.
double pull_angle(Direction d);

struct YarnSpec {
  std::string material;
  double denier = 0.0;                 // grams per 9,000 m of unstretched yarn
  std::optional<int> filaments;        // absent for spun yarns
  double mass_fraction = 0.0;          // share of the fabric's mass, in (0, 1]
  std::optional<double> stiffness;     // yarn stretch stiffness, force per unit strain [N]

  // Linear density [kg/m] = denier · 1e-3 kg / 9000 m.
  [[nodiscard]] double linear_density() const { return denier * 1e-3 / 9000.0; }
};

struct Swatch {
  double length = 0.0;  // free length between the clamps [m]
  double width = 0.0;   // fabric width [m]
};

// Gauge marks; either distance may be absent, and then that quantity is read from the
// clamps (length) or the free edges (width).
struct Gauge {
  std::optional<double> length;  // [m]
  std::optional<double> width;   // [m]
  [[nodiscard]] bool empty() const { return !length && !width; }
};

struct StretchCurve {
  std::vector<double> stretch;      // s, strictly increasing
  std::vector<double> force;        // total clamp force [N], ≥ 0
  std::vector<double> compression;  // c; empty when the rig did not measure width
  std::vector<int> source_lines;    // CSV line of each point
  [[nodiscard]] std::size_t size() const { return stretch.size(); }
  [[nodiscard]] bool has_compression() const { return !compression.empty(); }
};

struct StretchTest {
  Direction direction = Direction::weft;
  std::filesystem::path file;  // resolved path of the CSV
  Swatch swatch;               // this test's swatch (its own or the fabric's)
  Gauge gauge;
  StretchCurve curve;
  // Force per unit fabric width [N/m], the quantity the comfort range is stated in (SPEC §3).
  [[nodiscard]] double line_force(std::size_t i) const { return curve.force[i] / swatch.width; }
};

struct BendingCurve {
  std::vector<double> clamp_distance;  // d [m], strictly increasing
  std::vector<double> aspect_ratio;    // r = h/p of the pear loop, > 0
  std::vector<int> source_lines;
  [[nodiscard]] std::size_t size() const { return clamp_distance.size(); }
};

struct BendingTest {
  Direction direction = Direction::weft;
  std::filesystem::path file;
  Swatch swatch;
  BendingCurve curve;
};

enum class Axis { x, y };

// The knitting gauge as fabric specifications state it (SPEC §2 `knitting_gauge`): courses and
// wales per 10 cm of the relaxed fabric. A tile generated for the record is built at this
// period and holds it (issue 48).
struct KnittingGauge {
  double courses_per_10cm = 0.0;
  double wales_per_10cm = 0.0;
  [[nodiscard]] double course_spacing() const { return 0.1 / courses_per_10cm; }  // [m]
  [[nodiscard]] double wale_spacing() const { return 0.1 / wales_per_10cm; }      // [m]
  bool operator==(const KnittingGauge&) const = default;
};

// A tile to generate from the knit (`pattern: {knit: seed, stitch_length_mm: 15.67,
// yarn_radius_mm: 1.2}`, issue 20): made when a yarn fit needs it, never in the fabric's folder.
struct KnitSpec {
  KnitChart chart;
  double stitch_length = 0.0;  // [m]
  double yarn_radius = 0.0;    // [m]
  std::optional<KnittingGauge> gauge;  // the record's knitting_gauge: the period to hold
};

struct PatternRef {
  std::filesystem::path file;  // resolved path of the .pyp tile (the generated one, once made)
  Axis weft_axis = Axis::x;    // tile axis that runs along the weft
  std::optional<KnitSpec> knit;  // set: the tile is generated from it (file, tile and facts
                                 // are empty until then)
  PeriodicTile tile;
  TileFacts facts;             // computed once when the tile is read or generated
  [[nodiscard]] bool has_tile() const { return tile.vertex_count() > 0; }
};

struct Fabric {
  std::filesystem::path folder;     // folder holding fabric.yaml
  std::string id;
  std::string family;
  std::string description;
  std::optional<double> areal_density;  // [kg/m²]; required by pear-loop tests (gravity)
  std::vector<YarnSpec> yarns;
  std::optional<PatternRef> pattern;
  std::optional<Swatch> swatch;         // the fabric's default swatch
  std::optional<KnittingGauge> knitting_gauge;  // as the fabric's specification states it
  std::optional<double> thickness;      // [m], as stated
  std::map<Direction, StretchTest> stretch_tests;
  std::map<Direction, BendingTest> bending_tests;
  // A Browzwear FAB's tests, every cycle and branch (`fab_tests`, docs/fab.md), per direction
  // in protocol order; empty for other records.
  std::map<Direction, std::vector<FabTest>> fab_tests;
  std::optional<FabSource> fab_source;
  nlohmann::json ground_truth = nlohmann::json::object();  // synthetic fabrics only

  // Stretch stiffness of the stiffest yarn [N] (sets ks2, SPEC §3), if any yarn states one.
  [[nodiscard]] std::optional<double> stiffest_yarn_stiffness() const;
};

}  // namespace yarnfit::db
