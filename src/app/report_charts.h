// The report's chart kinds (rayes report, app/report_page.h), each drawn as hand-written inline
// SVG so that a page needs no script library and no network. Pure functions of their data:
// the same numbers give the same bytes. Every drawn datum is an element of class "mark" with a
// <title> (the browser's tooltip is the read-out of its value); a chart is only asked for when
// it has data, so a chart without marks is a bug that the browser test catches.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace rayes {

// Horizontal bars, one per row, scaled to the largest; an outlier is drawn in red and named so.
struct Bar {
  std::string label;
  double value = 0;
  std::string note;
  bool outlier = false;
};
std::string barChart(const std::string& title, const std::vector<Bar>& bars, const std::string& unit);  // report_bar_chart.cpp

// Columns, one group per category (a generation, a file, a level); each series one value per
// category, stacked (parts of a whole) or side by side (two runs). Outlier categories are marked.
struct Series {
  std::string name;
  std::vector<double> values;
};
struct ColumnChart {
  ColumnChart(std::string title, std::string unit, std::vector<std::string> categories, std::vector<Series> series,
              bool stacked = true)
      : title(std::move(title)), unit(std::move(unit)), categories(std::move(categories)), series(std::move(series)),
        stacked(stacked) {}
  std::string title, unit;
  std::vector<std::string> categories;
  std::vector<Series> series;
  bool stacked = true;
  std::vector<bool> outliers;  // per category, may be empty
};
std::string columnChart(const ColumnChart& c);  // report_column_chart.cpp

// Lines through points (x, y), on linear or log10 axes; a dashed line is a guide (e.g. the
// 1/sqrt(t) slope), not data. Point labels (e.g. "4 spp") are written beside the points.
struct LinePoint {
  double x = 0, y = 0;
  std::string label;
};
struct Line {
  std::string name;
  std::vector<LinePoint> points;
  bool guide = false;
};
struct LineChart {
  LineChart(std::string title, std::string xTitle, std::string yTitle, bool logX = false, bool logY = false)
      : title(std::move(title)), xTitle(std::move(xTitle)), yTitle(std::move(yTitle)), logX(logX), logY(logY) {}
  std::string title, xTitle, yTitle;
  std::vector<Line> lines;
  bool logX = false, logY = false;
};
std::string lineChart(const LineChart& c);  // report_line_chart.cpp

// The colour of series i, shared by the chart kinds and their legends.
const char* seriesColour(size_t i);

}  // namespace rayes
