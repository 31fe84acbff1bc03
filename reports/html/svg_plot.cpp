#include "reports/html/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace yarnfit::reports::svg {

namespace {

constexpr double k_char_px = 6.3;  // width of an 11 px character, estimated (sans-serif)
constexpr double k_font_px = 11.0;

std::string fmt(double v) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << v;
  return s.str();
}

double text_width(std::string_view text) { return k_char_px * static_cast<double>(text.size()); }

bool finite(double v) { return std::isfinite(v); }

// Data range of a set of values (positive only for log axes); false when there is none.
bool data_range(const std::vector<const std::vector<double>*>& lists, bool log, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (const auto* l : lists)
    for (double v : *l)
      if (finite(v) && (!log || v > 0.0)) lo = std::min(lo, v), hi = std::max(hi, v);
  return lo <= hi;
}

// Legend entries laid out in rows of at most `width` px; returns the number of rows.
struct LegendItem {
  std::string label, colour;
  Marker marker = Marker::circle;
  bool line = false, dashed = false, markers = true;
};
int legend(Canvas& c, const std::vector<LegendItem>& items, double x0, double y0, double width, bool draw) {
  double x = x0;
  int rows = items.empty() ? 0 : 1;
  for (const auto& it : items) {
    const double w = 26 + text_width(it.label) + 14;
    if (x > x0 && x + w > x0 + width) {
      x = x0;
      ++rows;
    }
    const double y = y0 + (rows - 1) * 16;
    if (draw) {
      if (it.line)
        c.line(x, y, x + 20, y, "stroke:" + it.colour + ";stroke-width:2" + (it.dashed ? ";stroke-dasharray:4 3" : ""));
      if (it.markers) c.marker(it.marker, x + 10, y, 7, it.colour);
      c.text(x + 25, y + 4, it.label, "start", "legend");
    }
    x += w;
  }
  return rows;
}

}  // namespace

const std::vector<std::string>& palette() {
  // Yellow last: on white it is the hardest to see.
  static const std::vector<std::string> p{"#0072B2", "#E69F00", "#009E73", "#CC79A7",
                                          "#56B4E9", "#D55E00", "#000000", "#F0E442"};
  return p;
}

Marker marker_for(std::size_t i) {
  static constexpr Marker m[] = {Marker::circle, Marker::square, Marker::triangle, Marker::diamond};
  return m[i % 4];
}

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        // Control characters are not allowed in XML 1.0 (a message could carry one).
        if (static_cast<unsigned char>(ch) < 0x20 && ch != '\n' && ch != '\t') out += ' ';
        else out += ch;
    }
  }
  return out;
}

std::string number_label(double v) {
  if (!finite(v)) return "–";
  if (v == 0.0) return "0";
  const double a = std::abs(v);
  std::ostringstream s;
  if (a >= 1e-3 && a < 1e4) s << std::setprecision(3) << v;
  else s << std::setprecision(2) << std::scientific << v;
  std::string t = s.str();
  // 1.00e-05 → 1e-05
  const auto e = t.find('e');
  if (e != std::string::npos) {
    std::string mant = t.substr(0, e);
    if (mant.find('.') != std::string::npos) {
      while (mant.back() == '0') mant.pop_back();
      if (mant.back() == '.') mant.pop_back();
    }
    t = mant + t.substr(e);
  }
  return t;
}

double Scale::operator()(double v) const {
  const double f = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
  return p0 + f * (p1 - p0);
}

std::vector<double> Scale::ticks() const {
  std::vector<double> t;
  if (log) {
    const int d0 = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
    const int d1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
    const bool fine = d1 - d0 < 3;
    const int stride = std::max(1, (d1 - d0 + 6) / 7);
    for (int d = d0; d <= d1; d += (fine ? 1 : stride)) {
      for (double m : fine ? std::vector<double>{1, 2, 5} : std::vector<double>{1}) {
        const double v = m * std::pow(10.0, d);
        if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
      }
    }
    return t;
  }
  const double span = hi - lo;
  const double raw = span / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * mag * 1.0001) {
      step = m * mag;
      break;
    }
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * span; v += step)
    t.push_back(std::abs(v) < 1e-12 * span ? 0.0 : v);
  return t;
}

void nice_range(double& lo, double& hi, bool log) {
  if (log) {
    if (!(lo > 0.0)) lo = hi > 0.0 ? hi / 10.0 : 1.0;
    if (!(hi > lo)) hi = lo * 10.0;
    lo = std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
    hi = std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
    if (hi <= lo) hi = lo * 10.0;
    return;
  }
  if (!(hi > lo)) {
    const double a = std::max(std::abs(lo), 1e-12);
    lo -= 0.5 * a;
    hi += 0.5 * a;
  }
  Scale s{lo, hi, false, 0, 1};
  const auto t = s.ticks();
  if (t.size() >= 2) {
    // Round the ends out to a tick unless that adds more than a tenth of the range (a curve a
    // hair below zero must not open a whole tick of empty axis): then leave a small margin.
    const double step = t[1] - t[0], span = hi - lo;
    const double nlo = std::floor(lo / step + 1e-9) * step, nhi = std::ceil(hi / step - 1e-9) * step;
    lo = lo - nlo > 0.1 * span ? lo - 0.03 * span : nlo;
    hi = nhi - hi > 0.1 * span ? hi + 0.03 * span : nhi;
  }
}

Canvas::Canvas(double width, double height, std::string attributes)
    : m_width(width), m_height(height), m_attributes(std::move(attributes)) {}

void Canvas::line(double x1, double y1, double x2, double y2, std::string_view style) {
  m_body += "<line x1=\"" + fmt(x1) + "\" y1=\"" + fmt(y1) + "\" x2=\"" + fmt(x2) + "\" y2=\"" + fmt(y2) +
            "\" style=\"" + std::string(style) + "\"/>";
}

void Canvas::rect(double x, double y, double w, double h, std::string_view style) {
  m_body += "<rect x=\"" + fmt(x) + "\" y=\"" + fmt(y) + "\" width=\"" + fmt(std::max(w, 0.0)) + "\" height=\"" +
            fmt(std::max(h, 0.0)) + "\" style=\"" + std::string(style) + "\"/>";
}

void Canvas::polyline(const std::vector<double>& x, const std::vector<double>& y, std::string_view style) {
  std::string pts;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!finite(x[i]) || !finite(y[i])) continue;
    pts += (pts.empty() ? "" : " ") + fmt(x[i]) + "," + fmt(y[i]);
  }
  if (!pts.empty()) m_body += "<polyline points=\"" + pts + "\" style=\"fill:none;" + std::string(style) + "\"/>";
}

void Canvas::marker(Marker m, double x, double y, double size, std::string_view colour, bool filled) {
  const std::string style = filled ? "fill:" + std::string(colour) + ";stroke:#fff;stroke-width:0.6"
                                   : "fill:#fff;stroke:" + std::string(colour) + ";stroke-width:1.5";
  const double r = size / 2;
  switch (m) {
    case Marker::circle:
      m_body += "<circle cx=\"" + fmt(x) + "\" cy=\"" + fmt(y) + "\" r=\"" + fmt(r) + "\" style=\"" + style + "\"/>";
      break;
    case Marker::square: rect(x - r * 0.9, y - r * 0.9, 1.8 * r, 1.8 * r, style); break;
    case Marker::triangle:
      m_body += "<polygon points=\"" + fmt(x) + "," + fmt(y - r * 1.1) + " " + fmt(x - r) + "," + fmt(y + r * 0.8) +
                " " + fmt(x + r) + "," + fmt(y + r * 0.8) + "\" style=\"" + style + "\"/>";
      break;
    case Marker::diamond:
      m_body += "<polygon points=\"" + fmt(x) + "," + fmt(y - r * 1.2) + " " + fmt(x + r) + "," + fmt(y) + " " +
                fmt(x) + "," + fmt(y + r * 1.2) + " " + fmt(x - r) + "," + fmt(y) + "\" style=\"" + style + "\"/>";
      break;
  }
}

void Canvas::text(double x, double y, std::string_view text, std::string_view anchor, std::string_view css_class,
                  double rotate) {
  m_body += "<text x=\"" + fmt(x) + "\" y=\"" + fmt(y) + "\" text-anchor=\"" + std::string(anchor) + "\"";
  if (!css_class.empty()) m_body += " class=\"" + std::string(css_class) + "\"";
  if (rotate != 0.0) m_body += " transform=\"rotate(" + fmt(rotate) + " " + fmt(x) + " " + fmt(y) + ")\"";
  m_body += ">" + escape(text) + "</text>";
}

void Canvas::title(std::string_view tooltip) { m_body += "<title>" + escape(tooltip) + "</title>"; }

void Canvas::raw(std::string_view svg) { m_body += svg; }

std::string Canvas::str() const {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(m_width) + "\" height=\"" + fmt(m_height) +
         "\" viewBox=\"0 0 " + fmt(m_width) + " " + fmt(m_height) + "\" " + m_attributes + ">" + m_body + "</svg>";
}

std::string render(const XYPlot& plot) {
  const double left = 62, right = 14, top = plot.title.empty() ? 10 : 26;
  const double plot_w = plot.width - left - right;
  std::vector<LegendItem> items;
  for (const auto& s : plot.series)
    if (!s.label.empty()) items.push_back({s.label, s.colour, s.marker, s.line, s.dashed, s.markers});
  for (const auto& m : plot.marks)
    if (!m.label.empty()) items.push_back({m.label, m.colour, Marker::circle, true, true, false});
  Canvas probe(0, 0, "");
  const int legend_rows = legend(probe, items, left, 0, plot_w, false);
  const double bottom = 40 + legend_rows * 16;
  const double height = plot.height + legend_rows * 16;
  Canvas c(plot.width, height, plot.attributes);
  const double y_top = top, y_bottom = height - bottom;

  std::vector<const std::vector<double>*> xs, ys;
  for (const auto& s : plot.series) xs.push_back(&s.x), ys.push_back(&s.y);
  double x0, x1, y0, y1;
  const bool any = data_range(xs, plot.x_log, x0, x1) && data_range(ys, plot.y_log, y0, y1);
  if (!plot.title.empty()) c.text(left, 16, plot.title, "start", "plot-title");
  if (!any) {
    c.text(left + plot_w / 2, (y_top + y_bottom) / 2, "no data", "middle", "note");
    return c.str();
  }
  for (const auto& m : plot.marks)
    if (finite(m.x) && (!plot.x_log || m.x > 0)) x0 = std::min(x0, m.x), x1 = std::max(x1, m.x);
  if (!plot.y_log && plot.y_from_zero) y0 = std::min(y0, 0.0), y1 = std::max(y1, 0.0);
  if (!plot.x_log && x0 > 0 && x0 < 0.25 * (x1 - x0)) x0 = 0.0;
  nice_range(x0, x1, plot.x_log);
  nice_range(y0, y1, plot.y_log);
  const Scale sx{x0, x1, plot.x_log, left, left + plot_w};
  const Scale sy{y0, y1, plot.y_log, y_bottom, y_top};

  c.rect(left, y_top, plot_w, y_bottom - y_top, "fill:#fff;stroke:#888;stroke-width:1");
  for (double t : sx.ticks()) {
    const double x = sx(t);
    c.line(x, y_top, x, y_bottom, "stroke:#e6e6e6;stroke-width:1");
    c.line(x, y_bottom, x, y_bottom + 4, "stroke:#555");
    c.text(x, y_bottom + 15, number_label(t), "middle", "tick");
  }
  for (double t : sy.ticks()) {
    const double y = sy(t);
    c.line(left, y, left + plot_w, y, "stroke:#e6e6e6;stroke-width:1");
    c.line(left - 4, y, left, y, "stroke:#555");
    c.text(left - 6, y + 4, number_label(t), "end", "tick");
  }
  c.text(left + plot_w / 2, y_bottom + 31, plot.x_label, "middle", "axis-label");
  c.text(14, (y_top + y_bottom) / 2, plot.y_label, "middle", "axis-label", -90);
  for (const auto& m : plot.marks) {
    if (!finite(m.x) || (plot.x_log && m.x <= 0)) continue;
    c.line(sx(m.x), y_top, sx(m.x), y_bottom, "stroke:" + m.colour + ";stroke-width:1.5;stroke-dasharray:4 3");
  }
  for (const auto& s : plot.series) {
    std::vector<double> px, py;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!finite(s.x[i]) || !finite(s.y[i]) || (plot.x_log && s.x[i] <= 0) || (plot.y_log && s.y[i] <= 0)) continue;
      px.push_back(sx(s.x[i]));
      py.push_back(sy(s.y[i]));
    }
    if (s.line)
      c.polyline(px, py, "stroke:" + s.colour + ";stroke-width:2" + (s.dashed ? ";stroke-dasharray:5 3" : ""));
    if (s.markers)
      for (std::size_t i = 0; i < px.size(); ++i) c.marker(s.marker, px[i], py[i], 7, s.colour, !s.line);
  }
  legend(c, items, left, height - bottom + 50 - 6, plot_w, true);
  return c.str();
}

std::string render(const DotPlot& plot) {
  const double row_h = 18, top = plot.title.empty() ? 12 : 30;
  double label_w = 40, group_w = 0;
  for (const auto& r : plot.rows) {
    label_w = std::max(label_w, text_width(r.label) + 10);
    group_w = std::max(group_w, text_width(r.group) + 14);
  }
  const double left = group_w + label_w, right = 16;
  const double plot_w = std::max(200.0, plot.width - left - right);
  const double width = left + plot_w + right;
  std::vector<LegendItem> items;
  for (std::size_t i = 0; i < plot.metrics.size(); ++i)
    items.push_back({plot.metrics[i], plot.group_legend.empty() ? palette()[i % palette().size()] : "#555",
                     marker_for(i)});
  for (const auto& [g, col] : plot.group_legend) items.push_back({g, col, Marker::square});
  Canvas probe(0, 0, "");
  const int legend_rows = legend(probe, items, left, 0, plot_w, false);
  const double body_h = row_h * static_cast<double>(std::max<std::size_t>(plot.rows.size(), 1));
  const double height = top + body_h + 40 + legend_rows * 16 + 6;
  Canvas c(width, height, plot.attributes);
  if (!plot.title.empty()) c.text(8, 18, plot.title, "start", "plot-title");

  double hi = plot.band * 1.5;
  for (const auto& r : plot.rows)
    for (double v : r.values)
      if (finite(v)) hi = std::max(hi, v);
  double lo = 0.0;
  nice_range(lo, hi, false);
  const Scale sx{0.0, hi, false, left, left + plot_w};
  const double y_bottom = top + body_h;
  c.rect(left, top, plot_w, body_h, "fill:#fff;stroke:#888");
  c.rect(left, top, sx(std::min(plot.band, hi)) - left, body_h, "fill:#dcebd5");
  for (double t : sx.ticks()) {
    c.line(sx(t), top, sx(t), y_bottom, "stroke:#e0e0e0");
    c.line(sx(t), y_bottom, sx(t), y_bottom + 4, "stroke:#555");
    c.text(sx(t), y_bottom + 15, number_label(t), "middle", "tick");
  }
  c.line(sx(plot.band), top, sx(plot.band), y_bottom, "stroke:#3a7d2c;stroke-width:1;stroke-dasharray:3 2");
  c.text(left + plot_w / 2, y_bottom + 31, plot.x_label, "middle", "axis-label");

  std::string group;
  double group_start = top;
  const auto close_group = [&](double y_end) {
    if (group.empty() && group_w == 0) return;
    c.text(6, (group_start + y_end) / 2 + 4, group, "start", "group-label");
    c.line(2, group_start + 2, 2, y_end - 2, "stroke:#888;stroke-width:2");
  };
  for (std::size_t k = 0; k < plot.rows.size(); ++k) {
    const auto& r = plot.rows[k];
    const double y = top + row_h * (static_cast<double>(k) + 0.5);
    if (k == 0 || r.group != group) {
      if (k > 0) {
        close_group(y - row_h / 2);
        c.line(group_w, y - row_h / 2, left + plot_w, y - row_h / 2, "stroke:#999");
      }
      group = r.group;
      group_start = y - row_h / 2;
    }
    if (k % 2 == 1) c.rect(left, y - row_h / 2, plot_w, row_h, "fill:#000;fill-opacity:0.035");
    c.text(left - 6, y + 4, r.label, "end", "row-label");
    for (std::size_t i = 0; i < r.values.size(); ++i) {
      const double v = r.values[i];
      if (!finite(v)) continue;
      const std::string colour = r.colour.empty() ? palette()[i % palette().size()] : r.colour;
      c.raw("<g>");
      // Metrics of a row a little apart vertically, so that equal values do not hide each other.
      const double dy = 2.0 * (static_cast<double>(i) - 0.5 * static_cast<double>(r.values.size() - 1));
      c.marker(marker_for(i), sx(std::min(v, hi)), y + dy, 8, colour);
      c.title(r.label + ": " + (i < plot.metrics.size() ? plot.metrics[i] : "") + " " + number_label(v) + " %");
      c.raw("</g>");
    }
  }
  if (!plot.rows.empty()) close_group(y_bottom);
  legend(c, items, left, y_bottom + 50, plot_w, true);
  return c.str();
}

std::string render(const BoundsPlot& plot) {
  const double row_h = 24, top = plot.title.empty() ? 10 : 28;
  double name_w = 40;
  for (const auto& v : plot.values) name_w = std::max(name_w, text_width(v.name + " [" + v.unit + "]") + 12);
  const double value_w = 150;
  const double left = name_w, right = value_w;
  const double bar_w = std::max(200.0, plot.width - left - right);
  const double height = top + row_h * static_cast<double>(plot.values.size()) + 26;
  Canvas c(left + bar_w + right, height, plot.attributes);
  if (!plot.title.empty()) c.text(8, 18, plot.title, "start", "plot-title");
  for (std::size_t k = 0; k < plot.values.size(); ++k) {
    const auto& v = plot.values[k];
    const double y = top + row_h * (static_cast<double>(k) + 0.5);
    c.text(left - 8, y + 4, v.name + (v.unit.empty() ? "" : " [" + v.unit + "]"), "end", "row-label");
    const bool usable = finite(v.lower) && finite(v.upper) && v.upper > v.lower && (!v.log || v.lower > 0);
    if (!usable) {
      c.text(left, y + 4, number_label(v.value) + " (no search range)", "start", "note");
      continue;
    }
    const Scale s{v.lower, v.upper, v.log, left + 6, left + bar_w - 6};
    c.rect(left + 6, y - 4, bar_w - 12, 8, "fill:#e8e8e8;stroke:#aaa");
    c.text(left + 6, y + 15, number_label(v.lower), "start", "tick");
    c.text(left + bar_w - 6, y + 15, number_label(v.upper), "end", "tick");
    const auto clamp = [&](double x) { return std::clamp(x, v.lower, v.upper); };
    const auto whisker = [&](double factor, const char* style) {
      if (!(factor > 1.0)) return;
      const double a = std::isinf(factor) ? v.lower : clamp(v.value / factor);
      const double b = std::isinf(factor) ? v.upper : clamp(v.value * factor);
      c.line(s(a), y, s(b), y, style);
      c.line(s(a), y - 5, s(a), y + 5, style);
      c.line(s(b), y - 5, s(b), y + 5, style);
    };
    whisker(v.range_refit, "stroke:#0072B2;stroke-width:2");
    whisker(v.range_held, "stroke:#E69F00;stroke-width:3");
    if (finite(v.value)) {
      const double x = s(clamp(v.value));
      c.raw("<g>");
      c.marker(Marker::circle, x, y, 9, v.on_bound ? "#D55E00" : "#000");
      c.title(v.name + " = " + number_label(v.value) + (v.on_bound ? " (on a search bound)" : ""));
      c.raw("</g>");
    }
    c.text(left + bar_w + 8, y + 4, number_label(v.value) + (v.on_bound ? "  ON BOUND" : ""), "start",
           v.on_bound ? "flag" : "value");
  }
  const double ly = height - 10;
  c.line(left + 6, ly - 4, left + 26, ly - 4, "stroke:#0072B2;stroke-width:2");
  c.text(left + 30, ly, "range, others re-fitted (g doubles)", "start", "legend");
  c.line(left + 250, ly - 4, left + 270, ly - 4, "stroke:#E69F00;stroke-width:3");
  c.text(left + 274, ly, "range, others held", "start", "legend");
  c.marker(Marker::circle, left + 410, ly - 4, 8, "#D55E00");
  c.text(left + 418, ly, "on a search bound", "start", "legend");
  return c.str();
}

}  // namespace yarnfit::reports::svg
