// `rayes report --watch DIR -o job.html`: the page of a running job, rewritten as its parts
// write their statistics. DIR is polled (every --watch-interval seconds) for stats files
// (`*.json`) and finished films (`*.film`: a farm part's header holds its stats,
// docs/batch-and-farm.md); a file that cannot be read yet (being written, a checkpoint) is left
// for the next look. The page is rewritten only when what was found changed, through a
// temporary and a rename, so a browser never reads half a page; while the job runs it refreshes
// itself (<meta http-equiv=refresh>), and its last version does not. The job is complete when
// --watch-until N files were read, when every part 1…N of a farm split is there, or when a file
// named `complete` appears in DIR; SIGINT, SIGTERM or SIGHUP stop the watch with the page as it is.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <thread>
#include <unistd.h>
#include "app/commands.h"
#include "app/film_file.h"
#include "app/interrupt.h"
#include "app/report_format.h"
#include "app/report_page.h"
#include "app/report_stats_file.h"
#include "core/error.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;

// File names in the order a person counts parts: "part-2" before "part-10".
bool naturalLess(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t i1 = i, j1 = j;
      while (i1 < a.size() && std::isdigit(static_cast<unsigned char>(a[i1]))) ++i1;
      while (j1 < b.size() && std::isdigit(static_cast<unsigned char>(b[j1]))) ++j1;
      const std::string x = a.substr(i, i1 - i), y = b.substr(j, j1 - j);
      if (x.size() != y.size()) return x.size() < y.size();
      if (x != y) return x < y;
      i = i1, j = j1;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

struct Look {
  std::vector<StatsFile> runs;
  std::string state;  // what was read (names, sizes, times): the page is rewritten when it changes
  int partsFound = 0, partsTotal = 0;
  bool markerFound = false;
};

Look lookAt(const std::string& dir, const std::string& out) {
  Look l;
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name == "complete") l.markerFound = true;
    const std::string ext = lowerExtension(name);
    if ((ext == ".json" || ext == ".film") && name[0] != '.' && fs::absolute(e.path()) != fs::absolute(out))
      names.push_back(name);
  }
  std::sort(names.begin(), names.end(), naturalLess);
  std::set<int> parts;
  for (const std::string& name : names) {
    const std::string path = (fs::path(dir) / name).string();
    try {
      StatsFile f = readStatsFile(path);
      if (lowerExtension(name) == ".film") {
        const FilmFileHeader h = readFilmFileHeader(path);
        if (h.kind == "part" && h.complete) {
          parts.insert(h.part);
          l.partsTotal = h.parts;
        }
      }
      l.state += name + ":" + std::to_string(fs::file_size(path, ec)) + ":" +
                 std::to_string(fs::last_write_time(path, ec).time_since_epoch().count()) + ";";
      l.runs.push_back(std::move(f));
    } catch (const InputError&) {
      // Not readable yet (being written), or not a finished run's: looked at again next time.
    }
  }
  l.partsFound = int(parts.size());
  return l;
}

// Through a temporary beside it and a rename: a reader sees the old page or the new one.
void writeAtomically(const std::string& out, const std::string& text) {
  const fs::path target(out);
  const fs::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    f.close();
    if (!f) throw ResourceError("-o", "cannot write " + tmp.string() + " (disk full?)");
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(out, "", "cannot write the page: " + ec.message());
  }
}

std::string statusLine(const std::string& dir, const Look& l, bool done, bool stopped, double interval) {
  std::string s = "<p class=" + std::string(done ? "note" : "warn") + " id=watch-status data-done=" + (done ? "1" : "0") +
                  ">Watching " + htmlEscape(dir) + ": " + std::to_string(l.runs.size()) + " stats read";
  if (l.partsTotal > 0) s += ", " + std::to_string(l.partsFound) + " of " + std::to_string(l.partsTotal) + " parts";
  if (done) s += stopped ? "; the watch was stopped (the job may still run)." : "; the job is complete.";
  else s += "; this page reloads every " + shortNumber(std::max(1.0, 2 * interval)) + " s while the job runs.";
  return s + "</p>";
}

std::string pageOf(const std::string& dir, const Look& l, bool done, bool stopped, double interval) {
  std::string page = l.runs.empty()
                         ? pageSkeleton("rayes report: watching " + dir, "<h1>rayes report: waiting for the job's first statistics</h1>")
                         : reportPage(l.runs);
  const size_t body = page.find("<body>");
  if (body != std::string::npos) page.insert(body + 6, statusLine(dir, l, done, stopped, interval));
  if (!done) {
    const size_t head = page.find("<head>");
    const int seconds = int(std::max(1.0, 2 * interval));
    if (head != std::string::npos) page.insert(head + 6, "<meta http-equiv=refresh content=" + std::to_string(seconds) + ">");
  }
  return page;
}

}  // namespace

int runReportWatch(const ReportArgs& a) {
  std::error_code ec;
  if (!fs::is_directory(a.watch, ec)) throw InputError(a.watch, "", "--watch needs the job's folder: not a folder");
  if (!a.stats.empty()) throw InputError("--watch", "", "reads the stats in the folder: give no stats files besides it");
  if (a.compare) throw InputError("--watch", "", "a watched job is not a comparison: leave out --compare");
  if (!(a.watchInterval > 0) || !std::isfinite(a.watchInterval))
    throw InputError("--watch-interval", "", "must be a positive number of seconds");
  if (a.watchUntil < 0) throw InputError("--watch-until", "", "must be a number of files, 1 or more (0: no such bound)");
  setStopOnSignal(true);
  struct Restore {
    ~Restore() { setStopOnSignal(false); }
  } restore;
  std::optional<std::string> written;  // what the page shows; none: no page yet
  for (;;) {
    const Look l = lookAt(a.watch, a.out);
    const bool complete = (a.watchUntil > 0 && int(l.runs.size()) >= a.watchUntil) || l.markerFound ||
                          (l.partsTotal > 0 && l.partsFound >= l.partsTotal);
    const bool stopped = !complete && stopRequested();
    const bool done = complete || stopped;
    const std::string key = l.state + (done ? "|done" : "");
    if (key != written) {
      writeAtomically(a.out, pageOf(a.watch, l, done, stopped, a.watchInterval));
      written = key;
      if (!a.quiet) std::fprintf(stderr, "rayes: wrote %s (%zu stats)%s\n", a.out.c_str(), l.runs.size(), done ? ", done" : "");
    }
    if (done) return 0;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(a.watchInterval);
    while (std::chrono::steady_clock::now() < until && !stopRequested())
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace rayes
