// Columns as SVG (report_charts.h): categories along x, series stacked or side by side, a
// linear y axis from 0 with three gridlines, a legend when there are several series.
#include <algorithm>
#include <cmath>
#include <sstream>
#include "app/report_charts.h"
#include "app/report_format.h"

namespace rayes {
namespace {

// The smallest 1, 2 or 5 × 10^k at or above v (v > 0): the axis's top.
double niceCeiling(double v) {
  const double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= v * (1 - 1e-12)) return m * p;
  return 10 * p;
}

std::string valueText(double v, const std::string& unit) { return unit == " B" ? shortBytes(v) : shortCount(v) + unit; }

}  // namespace

std::string columnChart(const ColumnChart& c) {
  const size_t n = c.categories.size(), k = c.series.size();
  constexpr int left = 70, right = 10, topMargin = 10, bottom = 46;
  // Wide enough for the labels when it can be; beyond 900 px, only every few are written.
  size_t longest = 1;
  for (const std::string& l : c.categories) longest = std::max(longest, l.size());
  const double labelW = 6.5 * double(longest) + 8;
  const int perCategory = std::max(int(labelW), c.stacked ? 28 : 18 * int(k) + 10);
  const int plotW = std::max(200, std::min(900, int(n) * perCategory));
  const int plotH = 170, width = left + plotW + right, legendH = k > 1 ? 20 : 0;
  const int height = topMargin + plotH + bottom + legendH;
  double top = 0;
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (const Series& s : c.series) {
      const double v = i < s.values.size() ? std::max(0.0, s.values[i]) : 0.0;
      sum = c.stacked ? sum + v : std::max(sum, v);
    }
    top = std::max(top, sum);
  }
  top = top > 0 ? niceCeiling(top) : 1.0;
  const double slot = double(plotW) / double(std::max<size_t>(n, 1));
  const double barW = c.stacked ? slot * 0.75 : slot * 0.8 / double(std::max<size_t>(k, 1));
  const auto yOf = [&](double v) { return topMargin + plotH - plotH * v / top; };
  std::ostringstream o;
  o << "<figure class=chart><figcaption>" << htmlEscape(c.title) << "</figcaption><svg class=chart width=" << width
    << " height=" << height << " viewBox=\"0 0 " << width << ' ' << height << "\" role=img>";
  for (int g = 0; g <= 2; ++g) {
    const double v = top * g / 2, y = yOf(v);
    o << "<line x1=" << left << " x2=" << left + plotW << " y1=" << shortNumber(y, 5) << " y2=" << shortNumber(y, 5)
      << " class=grid /><text x=" << left - 4 << " y=" << shortNumber(y + 4, 5) << " text-anchor=end class=axis>"
      << htmlEscape(valueText(v, c.unit)) << "</text>";
  }
  const size_t labelEvery = std::max<size_t>(1, size_t(std::ceil(double(n) * labelW / plotW)));
  for (size_t i = 0; i < n; ++i) {
    const bool outlier = i < c.outliers.size() && c.outliers[i];
    const double x0 = left + slot * double(i) + (slot - (c.stacked ? barW : barW * double(k))) / 2;
    double base = 0;
    for (size_t j = 0; j < k; ++j) {
      const double v = i < c.series[j].values.size() ? std::max(0.0, c.series[j].values[i]) : 0.0;
      const double x = c.stacked ? x0 : x0 + barW * double(j);
      const double y0 = yOf((c.stacked ? base : 0) + v), yb = c.stacked ? yOf(base) : yOf(0);
      // A zero keeps a hairline so that the datum is visible and hoverable.
      const double h = std::max(1.0, yb - y0);
      o << "<rect class=mark x=" << shortNumber(x, 6) << " y=" << shortNumber(yb - h, 6) << " width="
        << shortNumber(std::max(1.0, barW - 1), 5) << " height=" << shortNumber(h, 5) << " fill=\""
        << (outlier && k == 1 ? "#d03030" : seriesColour(j)) << "\"><title>" << htmlEscape(c.categories[i])
        << (k > 1 ? " " + c.series[j].name : "") << ": " << htmlEscape(valueText(v, c.unit)) << "</title></rect>";
      if (c.stacked) base += v;
    }
    if (outlier)
      o << "<text x=" << shortNumber(left + slot * (double(i) + 0.5), 5) << " y=" << topMargin + 10
        << " text-anchor=middle class=outlier>&#9650;<title>outlier</title></text>";
    if (i % labelEvery == 0)
      o << "<text x=" << shortNumber(left + slot * (double(i) + 0.5), 5) << " y=" << topMargin + plotH + 14
        << " text-anchor=middle class=axis>" << htmlEscape(c.categories[i]) << "</text>";
  }
  o << "<line x1=" << left << " x2=" << left + plotW << " y1=" << topMargin + plotH << " y2=" << topMargin + plotH
    << " class=axisline />";
  if (k > 1) {
    double x = left;
    for (size_t j = 0; j < k; ++j) {
      o << "<rect x=" << shortNumber(x, 5) << " y=" << height - 14 << " width=10 height=10 fill=\"" << seriesColour(j)
        << "\"/><text x=" << shortNumber(x + 14, 5) << " y=" << height - 5 << " class=axis>"
        << htmlEscape(c.series[j].name) << "</text>";
      x += 24 + 7.0 * double(c.series[j].name.size());
    }
  }
  o << "</svg></figure>";
  return o.str();
}

}  // namespace rayes
