// Horizontal bars as SVG (report_charts.h): a label column, the bar, the value and a note.
#include <algorithm>
#include <sstream>
#include "app/report_charts.h"
#include "app/report_format.h"

namespace rayes {

const char* seriesColour(size_t i) {
  static const char* colours[] = {"#4a7fb5", "#e39b3b", "#5aa65a", "#9b6bb5", "#c9b23c", "#3fb0b0", "#b5705a", "#777777"};
  return colours[i % (sizeof colours / sizeof colours[0])];
}

std::string barChart(const std::string& title, const std::vector<Bar>& bars, const std::string& unit) {
  constexpr int rowH = 20, labelW = 170, barW = 300, valueW = 90, noteW = 380;
  const int width = labelW + barW + valueW + noteW, height = rowH * int(bars.size()) + 6;
  double top = 0;
  for (const Bar& b : bars) top = std::max(top, b.value);
  std::ostringstream o;
  o << "<figure class=chart><figcaption>" << htmlEscape(title) << "</figcaption><svg class=chart width=" << width
    << " height=" << height << " viewBox=\"0 0 " << width << ' ' << height << "\" role=img>";
  for (size_t i = 0; i < bars.size(); ++i) {
    const Bar& b = bars[i];
    const int y = 3 + rowH * int(i);
    const double w = top > 0 ? std::max(1.0, barW * std::max(0.0, b.value) / top) : 1.0;
    const std::string value = (unit == " B" ? shortBytes(b.value) : shortNumber(b.value) + unit);
    o << "<text x=" << labelW - 6 << " y=" << y + 14 << " text-anchor=end>" << htmlEscape(b.label) << "</text>"
      << "<rect class=mark x=" << labelW << " y=" << y + 3 << " width=" << shortNumber(w, 5) << " height=" << rowH - 6
      << " fill=\"" << (b.outlier ? "#d03030" : seriesColour(0)) << "\"><title>" << htmlEscape(b.label) << ": "
      << htmlEscape(value) << "</title></rect>"
      << "<text x=" << labelW + barW + 6 << " y=" << y + 14 << " class=num>" << htmlEscape(value) << "</text>"
      << "<text x=" << labelW + barW + valueW << " y=" << y + 14 << " class=note>"
      << htmlEscape((b.outlier ? "outlier. " : "") + b.note) << "</text>";
  }
  o << "</svg></figure>";
  return o.str();
}

}  // namespace rayes
