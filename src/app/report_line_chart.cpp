// Lines as SVG (report_charts.h): linear or log10 axes fitted to the data (guides included),
// ticks at powers of ten on log axes, a legend, and the points' labels beside them.
#include <algorithm>
#include <cmath>
#include <sstream>
#include "app/report_charts.h"
#include "app/report_format.h"

namespace rayes {
namespace {

struct Axis {
  bool log = false;
  double lo = 0, hi = 1;  // in axis units (log10 of the value on a log axis)
  double toUnit(double v) const { return log ? std::log10(v) : v; }
  bool usable(double v) const { return std::isfinite(v) && (!log || v > 0); }
  std::vector<double> ticks() const {  // values
    std::vector<double> t;
    if (log) {
      for (double e = std::ceil(lo - 1e-9); e <= hi + 1e-9; e += 1) t.push_back(std::pow(10.0, e));
      if (t.size() < 2) t = {std::pow(10.0, lo), std::pow(10.0, hi)};
    } else {
      for (int i = 0; i <= 4; ++i) t.push_back(lo + (hi - lo) * i / 4);
    }
    return t;
  }
};

Axis fit(bool log, const std::vector<double>& values) {
  Axis a{log};
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (a.usable(v)) lo = std::min(lo, a.toUnit(v)), hi = std::max(hi, a.toUnit(v));
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (!log) lo = std::min(lo, 0.0);
  if (hi - lo < 1e-12) hi = lo + (log ? 1.0 : std::max(1.0, std::fabs(lo)));
  const double pad = (hi - lo) * 0.05;
  a.lo = log ? lo - pad : lo;
  a.hi = hi + pad;
  return a;
}

}  // namespace

std::string lineChart(const LineChart& c) {
  std::vector<double> xs, ys;
  for (const Line& l : c.lines)
    for (const LinePoint& p : l.points) xs.push_back(p.x), ys.push_back(p.y);
  const Axis ax = fit(c.logX, xs), ay = fit(c.logY, ys);
  constexpr int left = 70, right = 20, topMargin = 10, plotW = 560, plotH = 220, bottom = 40;
  // The legend names at most kLegend lines (an lbt render has dozens of generations); the
  // rest are counted, and each point still names its line in its read-out.
  constexpr size_t kLegend = 12;
  const size_t named = std::min(c.lines.size(), kLegend);
  const int legendH = 16 * int(named + (c.lines.size() > named ? 1 : 0));
  const int width = left + plotW + right, height = topMargin + plotH + bottom + legendH;
  const auto X = [&](double v) { return left + plotW * (ax.toUnit(v) - ax.lo) / (ax.hi - ax.lo); };
  const auto Y = [&](double v) { return topMargin + plotH - plotH * (ay.toUnit(v) - ay.lo) / (ay.hi - ay.lo); };
  std::ostringstream o;
  o << "<figure class=chart><figcaption>" << htmlEscape(c.title) << "</figcaption><svg class=chart width=" << width
    << " height=" << height << " viewBox=\"0 0 " << width << ' ' << height << "\" role=img>";
  for (double t : ay.ticks())
    o << "<line x1=" << left << " x2=" << left + plotW << " y1=" << shortNumber(Y(t), 5) << " y2=" << shortNumber(Y(t), 5)
      << " class=grid /><text x=" << left - 4 << " y=" << shortNumber(Y(t) + 4, 5) << " text-anchor=end class=axis>"
      << shortNumber(t) << "</text>";
  for (double t : ax.ticks())
    o << "<text x=" << shortNumber(X(t), 5) << " y=" << topMargin + plotH + 14 << " text-anchor=middle class=axis>"
      << shortNumber(t) << "</text>";
  o << "<text x=" << left + plotW / 2 << " y=" << topMargin + plotH + 30 << " text-anchor=middle class=axis>"
    << htmlEscape(c.xTitle) << (c.logX ? " (log)" : "") << "</text><text x=12 y=" << topMargin + plotH / 2
    << " class=axis transform=\"rotate(-90 12 " << topMargin + plotH / 2 << ")\" text-anchor=middle>"
    << htmlEscape(c.yTitle) << (c.logY ? " (log)" : "") << "</text>";
  for (size_t i = 0; i < c.lines.size(); ++i) {
    const Line& l = c.lines[i];
    const char* colour = l.guide ? "#999" : seriesColour(i);
    std::string d;
    for (const LinePoint& p : l.points)
      if (ax.usable(p.x) && ay.usable(p.y))
        d += (d.empty() ? "M" : " L") + shortNumber(X(p.x), 6) + "," + shortNumber(Y(p.y), 6);
    if (d.empty()) continue;
    o << "<path d=\"" << d << "\" fill=none stroke=\"" << colour << "\" stroke-width=" << (l.guide ? 1 : 2)
      << (l.guide ? " stroke-dasharray=\"5,4\"" : "") << " />";
    if (!l.guide)
      for (const LinePoint& p : l.points) {
        if (!ax.usable(p.x) || !ay.usable(p.y)) continue;
        o << "<circle class=mark cx=" << shortNumber(X(p.x), 6) << " cy=" << shortNumber(Y(p.y), 6) << " r=3 fill=\""
          << colour << "\"><title>" << htmlEscape(l.name) << ": " << htmlEscape(c.xTitle) << " " << shortNumber(p.x, 4)
          << ", " << htmlEscape(c.yTitle) << " " << shortNumber(p.y, 4) << (p.label.empty() ? "" : ", " + htmlEscape(p.label))
          << "</title></circle>";
        if (!p.label.empty())
          o << "<text x=" << shortNumber(X(p.x) + 4, 5) << " y=" << shortNumber(Y(p.y) - 5, 5) << " class=pointlabel>"
            << htmlEscape(p.label) << "</text>";
      }
    if (i >= named) continue;
    const int ly = topMargin + plotH + bottom + 16 * int(i) + 10;
    o << "<line x1=" << left << " x2=" << left + 24 << " y1=" << ly - 4 << " y2=" << ly - 4 << " stroke=\"" << colour
      << "\" stroke-width=2" << (l.guide ? " stroke-dasharray=\"5,4\"" : "") << " /><text x=" << left + 30 << " y=" << ly
      << " class=axis>" << htmlEscape(l.name) << "</text>";
  }
  if (c.lines.size() > named)
    o << "<text x=" << left << " y=" << topMargin + plotH + bottom + 16 * int(named) + 10 << " class=axis>… and "
      << c.lines.size() - named << " more lines</text>";
  o << "</svg></figure>";
  return o.str();
}

}  // namespace rayes
