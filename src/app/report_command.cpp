// `rayes report STATS.json... -o REPORT.html [--compare]`: the stats files of one render, a
// farm job's parts or a frame sequence as one self-contained page (app/report_page.h); with
// --compare, two runs side by side with ratios. Every file is read and checked before the
// page is built (app/report_stats_file.h), and the page is written all or nothing
// (app/output_set.h): bad input is one message naming the file and the JSON place, exit 2.
#include <cstdio>
#include "app/commands.h"
#include "app/output_set.h"
#include "app/report_page.h"
#include "app/report_pictures.h"
#include "app/report_stats_file.h"
#include "core/error.h"

namespace rayes {

int runReport(const ReportArgs& a) {
  if (!a.watch.empty()) {
    const std::string ext = lowerExtension(a.out);
    if (ext != ".html" && ext != ".htm") throw InputError("-o", "", a.out + ": the report is an HTML page: name it NAME.html");
    return runReportWatch(a);
  }
  if (a.stats.empty()) throw InputError("report", "", "no stats file given");
  const std::string ext = lowerExtension(a.out);
  if (ext != ".html" && ext != ".htm") throw InputError("-o", "", a.out + ": the report is an HTML page: name it NAME.html");
  if (a.compare && a.stats.size() != 2)
    throw InputError("--compare", "", "compares two runs: give two stats files, not " + std::to_string(a.stats.size()));
  OutputSet outputs;
  for (const std::string& path : a.stats) outputs.addInput(path);
  outputs.add(a.out, "report");
  std::vector<StatsFile> runs;
  for (const std::string& path : a.stats) runs.push_back(readStatsFile(path));
  if (a.compare) checkComparable(runs[0], runs[1]);
  // One run's per-pixel layers, from the image its stats name (--cost-layers).
  std::string note;
  const std::optional<CostPictures> pictures = runs.size() == 1 && !a.compare ? picturesOfStats(runs[0], note) : std::nullopt;
  outputs.writeText(a.out, a.compare ? comparisonPage(runs[0], runs[1])
                                     : reportPage(runs, {}, pictures ? &*pictures : nullptr, note));
  outputs.commit();
  if (!a.quiet) std::fprintf(stderr, "rayes: wrote %s\n", a.out.c_str());
  return 0;
}

}  // namespace rayes
