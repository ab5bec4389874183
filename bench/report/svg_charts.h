// Inline SVG charts for the benchmark reports: line/marker plots on linear or log
// axes and horizontal stacked bars, as self-contained <figure> strings (no scripts,
// no external resources). Pure functions of plain values; thread-safe.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace penumbra::bench {

struct Series {
  std::string name;
  std::vector<std::pair<double, double>> points;
  bool dashed = false;
  bool markersOnly = false;
  int colour = -1;  // index into the palette; -1: the series' position in the plot
};

struct Plot {
  std::string title, xLabel, yLabel;
  bool logX = false, logY = false;
  std::vector<Series> series;
  bool diagonal = false;     // draw y = x
  double legendWidth = 170;  // pixels right of the plot area for the legend
};

// One bar per label, split into parts (same order and count as `parts`).
struct StackedBars {
  std::string title, unit;
  std::vector<std::string> parts;  // legend, one colour each
  std::vector<std::pair<std::string, std::vector<double>>> bars;
};

// Text with <, > and & escaped for HTML and SVG.
std::string escapeHtml(const std::string& text);

// A number with three significant digits ("%.3g").
std::string shortNumber(double v);

// Points that are not finite, or not > 0 on a log axis, are left out.
std::string svgPlot(const Plot& plot);

// Bars scaled to the longest total; each labelled with its total and `unit`.
std::string svgStackedBars(const StackedBars& chart);

}  // namespace penumbra::bench
