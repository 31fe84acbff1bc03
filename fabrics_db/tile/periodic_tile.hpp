#pragma once
// A periodic yarn tile in the HYLC "pyp" layout (SPEC §6), in metres.
//
// The tile is a rectangle px × py in the x-y plane that repeats in x and y. Yarns are
// polylines of vertices; edge i runs from vertex v0 to the copy of vertex v1 shifted by
// (dx·px, dy·py), dx, dy ∈ {-1, 0, 1}. Every vertex has exactly one outgoing and one
// incoming edge, so the edges split into closed cycles: each cycle is one periodic yarn,
// and the sum of its edge offsets is the period it advances by (e.g. (1, 0) for a yarn
// running along the courses). Sections *RK, *RT and *RefT hold one entry per vertex,
// *RL and *RefD1 one per edge, in file order.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabrics_db/problems.hpp"

namespace yarnfit::db {

struct TileEdge {
  int v0 = 0;
  int v1 = 0;
  int dx = 0;  // period offset of v1 along x, in {-1, 0, 1}
  int dy = 0;  // period offset of v1 along y, in {-1, 0, 1}
};

struct PeriodicTile {
  double period_x = 0.0;  // px [m]
  double period_y = 0.0;  // py [m]
  double radius = 0.0;    // yarn radius as written in the file [m]

  std::vector<std::array<double, 3>> positions;        // *Q x y z, #V [m]
  std::vector<double> twists;                          // *Q t, #V (edge twist DOF) [rad]
  std::vector<TileEdge> edges;                         // *E, #E (== #V)
  std::vector<double> rest_lengths;                    // *RL, #E [m]
  std::vector<std::array<double, 2>> rest_curvatures;  // *RK, #V [1/m · m] (DER κb components)
  std::vector<double> rest_twists;                     // *RT, #V [rad]
  std::vector<std::array<double, 3>> reference_directors;  // *RefD1, #E, unit vectors
  std::vector<double> reference_twists;                // *RefT, #V [rad]

  [[nodiscard]] int vertex_count() const { return static_cast<int>(positions.size()); }
  [[nodiscard]] int edge_count() const { return static_cast<int>(edges.size()); }
  // End point of edge e's second vertex, with the period offset applied [m].
  [[nodiscard]] std::array<double, 3> edge_end(int e) const;
};

// Documented defaults for the optional sections, used by the reader when a section is
// absent and by code that builds tiles: each empty vector among twists (0), rest_lengths
// (geometric edge lengths), rest_curvatures (0 0), rest_twists (0), reference_directors
// (default_reference_director of the edge) and reference_twists (0) is filled in; vectors
// that already hold values are left alone.
void fill_tile_defaults(PeriodicTile& tile);
// A unit vector perpendicular to `tangent`: normalise(tangent × z), or, for a tangent
// (nearly) along z, the part of x perpendicular to it. (1, 0, 0) for a zero tangent.
std::array<double, 3> default_reference_director(const std::array<double, 3>& tangent);

// Reads a pyp file. Every problem is added to `problems` (file, line, section, message);
// the result is empty when any problem was found, so no caller sees a half-read tile.
// Sections start with a line "*NAME", optionally followed by "# comment"; blank lines and
// text after '#' are ignored; CRLF line endings are accepted. *pattern, *Q and *E are
// required, the others get the defaults of fill_tile_defaults. Rejected, each with its
// line and a field such as "*E v1": unknown or repeated sections, rows before the first
// section, a row count other than n (or 1 for *pattern), a file ending inside a section or
// before a required one, a wrong number of values on a row, text, NaN or Inf for a number,
// a non-integer in *E, non-positive px, py, radius or n, vertex indices outside [0, n),
// period offsets outside {-1, 0, 1}, a vertex without exactly one outgoing and one incoming
// edge, zero-length edges, non-positive rest lengths and reference directors that are not
// unit vectors (±1e-3: the HYLC files store single precision). A missing or unreadable file
// is one problem on line 0, field "file".
std::optional<PeriodicTile> read_pyp(const std::filesystem::path& file, Problems& problems);
// Same, from text already in memory; `file_label` is used in problem messages.
std::optional<PeriodicTile> parse_pyp(const std::string& text, const std::string& file_label,
                                      Problems& problems);

// Writes `tile` in pyp layout with `significant_digits` digits per value ("%.*g"; 17
// reproduces every double exactly): every section in the order and with the header comments
// of the HYLC files, a blank line after each. write_pyp replaces `file` through a temporary
// file in the same folder and a rename, and throws an Error naming the file if it
// cannot be written. Both throw an input Error if the tile's arrays disagree in size
// or significant_digits < 1.
void write_pyp(const PeriodicTile& tile, const std::filesystem::path& file,
               int significant_digits = 17);
std::string format_pyp(const PeriodicTile& tile, int significant_digits = 17);

struct PeriodicYarn {
  std::vector<int> edges;  // edge indices in order along the yarn
  int offset_x = 0;        // periods advanced in x after one trip along the yarn
  int offset_y = 0;
  double length = 0.0;     // geometric length of the polyline in the tile [m]
  double rest_length = 0.0;  // sum of *RL over its edges [m]
};

// Facts about a tile used for checks and for the yarn fit (SPEC §3).
struct TileFacts {
  std::vector<PeriodicYarn> yarns;
  double area = 0.0;               // px · py [m²]
  double total_length = 0.0;       // geometric yarn length in the tile [m]
  double total_rest_length = 0.0;  // sum of rest lengths [m]
  double yarn_radius = 0.0;        // as written in the file [m]
  double mean_segment_length = 0.0;  // [m]
  // R_est: the smallest radius at which every segment touches another one, i.e.
  //   R_est = max_a D_a / 2,  D_a = min over contact candidates b of dist(a, b),
  // with dist the exact centreline distance between segments. Candidates are all edges of
  // the tile and of its copies shifted by (i·px, j·py), except a itself and the two edges
  // sharing a vertex with it. Two segments on the same infinite yarn count only if the yarn
  // between them is longer than (π/2)·dist: a yarn of radius R touching itself through a
  // U-turn has at least πR of arc between points 2R apart, while nearby segments of a
  // straight yarn have arc ≈ distance. The copy of b shifted by s is on a's infinite yarn
  // when both are edges of one cycle and s + c_a − c_b = k·(net offset of the cycle), with
  // c_e the offsets summed along the cycle before edge e; the arc between them is then
  // measured with that copy k yarn lengths further along. (Comparing s alone with the net
  // offset, ignoring c, mistakes copies across the tile boundary and changes R_est when a
  // vertex is moved by a whole period.)
  double r_est = 0.0;
  int r_est_edge = -1;  // the edge a attaining the maximum
  // Smallest centreline distance between contact candidates [m]; 0 means yarns intersect.
  double min_contact_distance = 0.0;
  std::vector<double> segment_contact_distances;  // D_a per edge, #E [m]
};

// Throws an input Error for a tile that is not closed loops (see read_pyp) or whose
// edges span so many periods that the contact search would not end in reasonable time.
TileFacts compute_tile_facts(const PeriodicTile& tile);

// The centreline of one yarn unwrapped across the period boundaries: its first edge's first
// vertex, then each edge's end with the offsets so far applied, so consecutive points are
// neighbours in space; the last point is the first moved by the yarn's net offset [m].
std::vector<std::array<double, 3>> yarn_polyline(const PeriodicTile& tile, const PeriodicYarn& yarn);

}  // namespace yarnfit::db
