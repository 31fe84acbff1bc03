#pragma once
// Inline SVG plots for the HTML report: axes with ticks and units, linear or log scales,
// legends, markers of several shapes (so that colour is never the only cue), and the
// Okabe–Ito colour-blind-safe palette. Output is well-formed XML (every text escaped).

#include <string>
#include <string_view>
#include <vector>

namespace yarnfit::reports::svg {

// Okabe & Ito's eight colours, yellow last; the first is used first.
const std::vector<std::string>& palette();
enum class Marker { circle, square, triangle, diamond };
Marker marker_for(std::size_t i);

std::string escape(std::string_view text);
// A number for a tick or a label: 3 significant digits, 1e-3…1e4 plain, else 1.2e-05.
std::string number_label(double v);

// A linear or logarithmic map from data values [lo, hi] to pixels [p0, p1].
struct Scale {
  double lo = 0.0, hi = 1.0;
  bool log = false;
  double p0 = 0.0, p1 = 1.0;
  [[nodiscard]] double operator()(double v) const;
  // 4–8 "nice" ticks inside [lo, hi]: 1-2-5 steps, or decades (and 2, 5 within them when
  // fewer than three decades) for a log scale.
  [[nodiscard]] std::vector<double> ticks() const;
};

// Extends [lo, hi] to nice round ends (log: whole decades), and makes an empty range usable.
void nice_range(double& lo, double& hi, bool log);

// SVG elements, accumulated.
class Canvas {
 public:
  Canvas(double width, double height, std::string attributes);
  void line(double x1, double y1, double x2, double y2, std::string_view style);
  void rect(double x, double y, double w, double h, std::string_view style);
  void polyline(const std::vector<double>& x, const std::vector<double>& y, std::string_view style);
  void marker(Marker m, double x, double y, double size, std::string_view colour, bool filled = true);
  // anchor: start, middle, end; `rotate` turns the text about its anchor (degrees).
  void text(double x, double y, std::string_view text, std::string_view anchor = "start",
            std::string_view css_class = "", double rotate = 0.0);
  void title(std::string_view tooltip);  // a <title> for the last group
  void raw(std::string_view svg);
  [[nodiscard]] std::string str() const;

 private:
  double m_width, m_height;
  std::string m_attributes;
  std::string m_body;
};

struct Series {
  std::string label;
  std::vector<double> x, y;
  std::string colour;
  bool line = true;
  bool markers = false;
  Marker marker = Marker::circle;
  bool dashed = false;
};

struct VerticalMark {
  double x = 0.0;
  std::string colour;
  std::string label;
};

struct XYPlot {
  std::string title;
  std::string x_label, y_label;  // with their units
  bool x_log = false, y_log = false;
  bool y_from_zero = true;       // linear y axes start at 0 unless the data go below
  std::vector<Series> series;
  std::vector<VerticalMark> marks;
  double width = 420, height = 280;
  std::string attributes;  // e.g. class="…" data-fabric="…"
};
std::string render(const XYPlot& plot);

// A dot plot with a row per item (Fig. 6.13/6.15 of the thesis): rows grouped (a label per
// group in the gutter), a mark per metric, the band [0, band] shaded.
struct DotRow {
  std::string label;
  std::string group;
  std::string colour;              // of the row's marks (by group), or empty: by metric
  std::vector<double> values;      // one per metric, NaN for none
};
struct DotPlot {
  std::string title;
  std::string x_label;
  std::vector<std::string> metrics;  // legend names, marker i each
  std::vector<DotRow> rows;
  std::vector<std::pair<std::string, std::string>> group_legend;  // group → colour, when coloured by group
  double band = 10.0;
  double width = 760;
  std::string attributes;
};
std::string render(const DotPlot& plot);

// One row per parameter on its own log axis between its bounds: the range as a bar, the
// value as a dot (flagged when on a bound), and optional identifiability ranges as whiskers.
struct BoundedValue {
  std::string name, unit;
  double value = 0.0, lower = 0.0, upper = 0.0;
  bool log = true;
  bool on_bound = false;
  double range_refit = 0.0;  // × factor of the range with the others re-fitted; 0: none; inf: free
  double range_held = 0.0;   // the same with the others held
};
struct BoundsPlot {
  std::string title;
  std::vector<BoundedValue> values;
  double width = 760;
  std::string attributes;
};
std::string render(const BoundsPlot& plot);

}  // namespace yarnfit::reports::svg
