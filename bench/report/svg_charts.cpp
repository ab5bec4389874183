#include "bench/report/svg_charts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

namespace penumbra::bench {

namespace {

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                          "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

const char* colourOf(int index) { return kColours[size_t(index) % std::size(kColours)]; }

std::string svgOpen(double width, double height, const std::string& title) {
  return "<figure><svg xmlns='http://www.w3.org/2000/svg' width='" + shortNumber(width) +
         "' height='" + shortNumber(height) + "' viewBox='0 0 " + shortNumber(width) + " " +
         shortNumber(height) + "' font-family='sans-serif' font-size='11'><text x='" +
         shortNumber(width / 2) + "' y='18' text-anchor='middle' font-size='13'>" +
         escapeHtml(title) + "</text>";
}

// The plot area and the mapping of data to it (log10 on log axes).
struct Axes {
  static constexpr double H = 360, L = 70, T = 30, B = 45, Inner = 400;
  const Plot& plot;
  double ax0, ax1, ay0, ay1;
  double R = plot.legendWidth, W = L + Inner + R;
  double fx(double x) const { return plot.logX ? std::log10(x) : x; }
  double fy(double y) const { return plot.logY ? std::log10(y) : y; }
  double px(double x) const { return L + (fx(x) - ax0) / (ax1 - ax0) * (W - L - R); }
  double py(double y) const { return H - B - (fy(y) - ay0) / (ay1 - ay0) * (H - T - B); }
  bool usable(double x, double y) const {
    return std::isfinite(x) && std::isfinite(y) && (!plot.logX || x > 0) && (!plot.logY || y > 0);
  }
};

// Frame, ticks (5 per axis, at the transformed scale), axis labels and the diagonal.
std::string axesSvg(const Axes& a) {
  const Plot& plot = a.plot;
  const double W = a.W, H = Axes::H, L = Axes::L, R = a.R, T = Axes::T, B = Axes::B;
  std::string out = "<rect x='" + shortNumber(L) + "' y='" + shortNumber(T) + "' width='" +
                    shortNumber(W - L - R) + "' height='" + shortNumber(H - T - B) +
                    "' fill='none' stroke='#888'/>";
  for (int i = 0; i <= 4; ++i) {
    const double tx = a.ax0 + (a.ax1 - a.ax0) * i / 4, ty = a.ay0 + (a.ay1 - a.ay0) * i / 4;
    const double vx = plot.logX ? std::pow(10, tx) : tx, vy = plot.logY ? std::pow(10, ty) : ty;
    const double sx = L + (W - L - R) * i / 4, sy = H - B - (H - T - B) * i / 4;
    out += "<text x='" + shortNumber(sx) + "' y='" + shortNumber(H - B + 14) +
           "' text-anchor='middle'>" + shortNumber(vx) + "</text>";
    out += "<text x='" + shortNumber(L - 4) + "' y='" + shortNumber(sy + 4) +
           "' text-anchor='end'>" + shortNumber(vy) + "</text>";
    out += "<line x1='" + shortNumber(L) + "' x2='" + shortNumber(W - R) + "' y1='" +
           shortNumber(sy) + "' y2='" + shortNumber(sy) + "' stroke='#eee'/>";
  }
  out += "<text x='" + shortNumber((L + W - R) / 2) + "' y='" + shortNumber(H - 8) +
         "' text-anchor='middle'>" + escapeHtml(plot.xLabel + (plot.logX ? " (log)" : "")) +
         "</text>";
  out += "<text transform='translate(14," + shortNumber((T + H - B) / 2) +
         ") rotate(-90)' text-anchor='middle'>" +
         escapeHtml(plot.yLabel + (plot.logY ? " (log)" : "")) + "</text>";
  if (plot.diagonal) {
    const double p = plot.logX ? std::pow(10, a.ax0) : a.ax0;
    const double q = plot.logX ? std::pow(10, a.ax1) : a.ax1;
    out += "<line x1='" + shortNumber(a.px(p)) + "' y1='" + shortNumber(a.py(p)) + "' x2='" +
           shortNumber(a.px(q)) + "' y2='" + shortNumber(a.py(q)) +
           "' stroke='#aaa' stroke-dasharray='2,3'/>";
  }
  return out;
}

// One series' line (or markers) and its legend entry at position s.
std::string seriesSvg(const Axes& a, const Series& series, size_t s) {
  const std::string colour = colourOf(series.colour >= 0 ? series.colour : int(s));
  const std::string dash = series.dashed ? " stroke-dasharray='5,3'" : "";
  std::string out, path;
  for (auto [x, y] : series.points) {
    if (!a.usable(x, y)) continue;
    if (series.markersOnly || series.points.size() == 1)
      out += "<circle cx='" + shortNumber(a.px(x)) + "' cy='" + shortNumber(a.py(y)) +
             "' r='2.5' fill='" + colour + "'/>";
    path += (path.empty() ? "M" : " L") + shortNumber(a.px(x)) + "," + shortNumber(a.py(y));
  }
  if (!series.markersOnly && !path.empty())
    out += "<path d='" + path + "' fill='none' stroke='" + colour + "' stroke-width='1.5'" + dash +
           "/>";
  const double x = a.W - a.R, ly = Axes::T + 12 + 15 * double(s);
  out += "<line x1='" + shortNumber(x + 10) + "' x2='" + shortNumber(x + 30) + "' y1='" +
         shortNumber(ly - 4) + "' y2='" + shortNumber(ly - 4) + "' stroke='" + colour +
         "' stroke-width='2'" + dash + "/>";
  out += "<text x='" + shortNumber(x + 34) + "' y='" + shortNumber(ly) + "'>" +
         escapeHtml(series.name) + "</text>";
  return out;
}

}  // namespace

std::string escapeHtml(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string shortNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

std::string svgPlot(const Plot& plot) {
  Axes a{plot, INFINITY, -INFINITY, INFINITY, -INFINITY};
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Series& s : plot.series)
    for (auto [x, y] : s.points)
      if (a.usable(x, y))
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  std::string out = svgOpen(a.W, Axes::H, plot.title);
  if (!(x0 <= x1)) return out + "<text x='20' y='60'>no data</text></svg></figure>\n";
  a.ax0 = a.fx(x0), a.ax1 = a.fx(x1), a.ay0 = a.fy(y0), a.ay1 = a.fy(y1);
  if (plot.diagonal) a.ax0 = a.ay0 = std::min(a.ax0, a.ay0), a.ax1 = a.ay1 = std::max(a.ax1, a.ay1);
  if (a.ax1 - a.ax0 < 1e-12) a.ax0 -= 0.5, a.ax1 += 0.5;
  if (a.ay1 - a.ay0 < 1e-12) a.ay0 -= 0.5, a.ay1 += 0.5;
  if (!plot.logY && a.ay0 > 0) a.ay0 = 0;
  const double padY = 0.05 * (a.ay1 - a.ay0);
  a.ay1 += padY;
  if (plot.logY) a.ay0 -= padY;
  out += axesSvg(a);
  for (size_t s = 0; s < plot.series.size(); ++s) out += seriesSvg(a, plot.series[s], s);
  return out + "</svg></figure>\n";
}

std::string svgStackedBars(const StackedBars& chart) {
  constexpr double W = 640, L = 150, R = 70, T = 30, Bar = 16, Gap = 6, LegendRow = 18;
  const double H = T + double(chart.bars.size()) * (Bar + Gap) + 2 * LegendRow;
  double longest = 0;
  for (const auto& [label, values] : chart.bars) {
    double total = 0;
    for (double v : values) total += std::isfinite(v) && v > 0 ? v : 0;
    longest = std::max(longest, total);
  }
  std::string out = svgOpen(W, H, chart.title);
  if (!(longest > 0)) return out + "<text x='20' y='60'>no data</text></svg></figure>\n";
  const double scale = (W - L - R) / longest;
  for (size_t b = 0; b < chart.bars.size(); ++b) {
    const auto& [label, values] = chart.bars[b];
    const double y = T + double(b) * (Bar + Gap);
    double x = L, total = 0;
    for (size_t p = 0; p < values.size(); ++p) {
      const double v = std::isfinite(values[p]) && values[p] > 0 ? values[p] : 0;
      out += "<rect x='" + shortNumber(x) + "' y='" + shortNumber(y) + "' width='" +
             shortNumber(v * scale) + "' height='" + shortNumber(Bar) + "' fill='" +
             colourOf(int(p)) + "'/>";
      x += v * scale, total += v;
    }
    out += "<text x='" + shortNumber(L - 4) + "' y='" + shortNumber(y + Bar - 4) +
           "' text-anchor='end'>" + escapeHtml(label) + "</text>";
    out += "<text x='" + shortNumber(x + 4) + "' y='" + shortNumber(y + Bar - 4) + "'>" +
           shortNumber(total) + " " + escapeHtml(chart.unit) + "</text>";
  }
  const double ly = H - LegendRow;
  double x = L;
  for (size_t p = 0; p < chart.parts.size(); ++p) {
    out += "<rect x='" + shortNumber(x) + "' y='" + shortNumber(ly - 9) +
           "' width='10' height='10' fill='" + colourOf(int(p)) + "'/><text x='" +
           shortNumber(x + 14) + "' y='" + shortNumber(ly) + "'>" + escapeHtml(chart.parts[p]) +
           "</text>";
    x += 30 + 6.2 * double(chart.parts[p].size());  // about 6 px per character at 11 px
  }
  return out + "</svg></figure>\n";
}

}  // namespace penumbra::bench
