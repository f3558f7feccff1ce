// The report pages (`rayes report`, `rayes render --report`): self-contained HTML built from
// checked stats files (app/report_stats_file.h). Nothing is fetched when a page is viewed:
// styles, the small checking and read-out script, the charts (inline SVG, app/report_charts.h)
// and the preview image (a data: URI) are all in the file. Pure functions: the same stats give
// the same page. docs/dashboard.md explains every chart.
#pragma once
#include <string>
#include <vector>
#include "app/report_pictures.h"
#include "app/report_stats_file.h"

namespace rayes {

// One run's page, or with several files (a farm job's parts, a frame sequence) a summary of
// them side by side with outliers marked, then every run's charts in columns.
// previewPng: the bytes of a PNG shown at the top of a single run's page (may be empty).
// pictures: the per-pixel layers of a single run (app/report_pictures.h), drawn instead of the
// preview; picturesNote: why they are missing although the stats name them (shown as a warning).
std::string reportPage(const std::vector<StatsFile>& runs, const std::string& previewPng = {},
                       const CostPictures* pictures = nullptr, const std::string& picturesNote = {});

// Two runs of the same scene and resolution (checkComparable) side by side, with ratios B / A.
std::string comparisonPage(const StatsFile& a, const StatsFile& b);

// The page skeleton around a body: the title, the inline style and script (report_page.cpp).
std::string pageSkeleton(const std::string& title, const std::string& body);

}  // namespace rayes
