// `rayes report` and the report pages (app/report_*.h): what each page must show of the stats
// it is given, and the refusals: a stats file that is missing, empty, not JSON, of another
// version, or lacking a field; runs that cannot be compared; an output that cannot be written.
// Each refusal is one message naming the file (and the JSON place), exit code 2, nothing written.
// The pages in a real browser: report_browser_test.cpp.
#include <filesystem>
#include <fstream>
#include <regex>
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include <nlohmann/json.hpp>
#include "app/report_page.h"
#include "app/report_stats_file.h"
#include "app/stats_json.h"
#include "core/error.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

size_t occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// One small render with a reference (so the stats hold an error curve), made once.
class Report : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new testing::TempFolder;
    const auto p = [](const char* n) { return folder_->path(n); };
    ASSERT_EQ(testing::runRayes({"render", kScene, "--spp", "4", "--res", "16x12", "-o", p("ref.exr"), "-q"}).code, 0);
    const auto r = testing::runRayes({"render", kScene, "--spp", "4", "--seed", "3", "--res", "16x12", "-o", p("x.exr"),
                                      "--reference", p("ref.exr"), "--stats", p("s.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    stats_ = new json(json::parse(slurp(p("s.json"))));
  }
  static void TearDownTestSuite() {
    delete stats_;
    delete folder_;
  }
  static const json& stats() { return *stats_; }
  std::string write(const std::string& name, const std::string& text) const { return temp_.write(name, text); }
  std::string path(const std::string& name) const { return temp_.path(name); }
  testing::TempFolder temp_;

 private:
  static testing::TempFolder* folder_;
  static json* stats_;
};
testing::TempFolder* Report::folder_ = nullptr;
json* Report::stats_ = nullptr;

// Every chart on a page has at least one drawn datum (the browser test checks the drawing).
void expectNoEmptyChart(const std::string& html) {
  // Found by hand, not by std::regex: libstdc++'s executor recurses once per character of a
  // lazy match, and a chart of many points overflowed the stack under the sanitizers.
  size_t charts = 0;
  for (size_t at = html.find("<svg class=chart"); at != std::string::npos; at = html.find("<svg class=chart", at + 1)) {
    const size_t end = html.find("</svg>", at);
    ASSERT_NE(end, std::string::npos) << html.substr(at, 200);
    const std::string chart = html.substr(at, end - at);
    ++charts;
    EXPECT_THAT(chart, HasSubstr("class=mark")) << chart.substr(0, 200);
  }
  EXPECT_GT(charts, 0u);
  // An unquoted attribute value before "/>" swallows the slash in HTML: the element stays open
  // and what follows it is drawn inside it, or not at all.
  std::smatch m;
  EXPECT_FALSE(std::regex_search(html, m, std::regex("=[^\"'\\s>]+/>"))) << m.str();
}

TEST_F(Report, TheStatsAgreeOnTheDiceBuffersAndCountEveryDicingByLevel) {
  const json& s = stats();
  EXPECT_EQ(s["stats_version"].get<int>(), kStatsVersion);
  EXPECT_EQ(s["memory"]["dice_buffer_bytes"], s["memory"]["by_owner"]["dice_buffers"]);
  uint64_t byLevel = 0;
  for (const auto& [level, n] : s["totals"]["dicings_by_level"].items()) {
    EXPECT_LE(std::stoi(level), s["settings"]["max_lod"].get<int>());
    byLevel += n.get<uint64_t>();
  }
  EXPECT_EQ(byLevel, s["totals"]["leaves_diced"].get<uint64_t>());
  EXPECT_GT(byLevel, 0u);
}

TEST_F(Report, ASingleRunPageNamesTheMethodAndKeepsThreadAndWallTimeApart) {
  const std::string html = reportPage({{"s.json", stats()}});
  EXPECT_THAT(html, HasSubstr("<h1>rayes report: pt (path tracing)</h1>"));
  EXPECT_THAT(html, HasSubstr("Wall clock (seconds)"));
  EXPECT_THAT(html, HasSubstr("Thread time, summed over threads (seconds)"));
  for (const char* chart : {"Rays per generation", "Active rays per top-level iteration", "Candidates per ray per iteration",
                            "Dicings and grid-cache hits per generation", "Micropolygons created per generation",
                            "Rays per dicing per generation", "Level-of-detail histogram", "Memory by owner",
                            "Error against time (log-log)", "1/√t slope", "4 spp"})
    EXPECT_THAT(html, HasSubstr(chart));
  expectNoEmptyChart(html);
  // Self-contained: nothing is fetched when the page is viewed.
  EXPECT_THAT(html, Not(HasSubstr("http://")));
  EXPECT_THAT(html, Not(HasSubstr("https://")));
  EXPECT_THAT(html, Not(HasSubstr("<link")));
  EXPECT_EQ(reportPage({{"s.json", stats()}}), html);  // the same stats, the same page
}

TEST_F(Report, TheDiceBuffersBarShowsTheStatsFigure) {
  json s = stats();
  s["memory"]["by_owner"]["dice_buffers"] = 36280320;  // the 34.6 MiB
  EXPECT_THAT(reportPage({{"s.json", s}}), HasSubstr("dice_buffers: 34.6 MiB"));
}

TEST_F(Report, AMethodsOwnSectionIsShownWhenTheStatsHaveIt) {
  json s = stats();
  s["settings"]["method"] = "lbt";
  s["beams"] = {{"segments", 1200}, {"corner_rays", 5000}, {"peak_bytes", 13421772}, {"stopped", {{"mixed", 7}, {"divergent", 2}}}};
  const std::string html = reportPage({{"s.json", s}});
  EXPECT_THAT(html, HasSubstr("<h1>rayes report: lbt (light beam tracing)</h1>"));
  EXPECT_THAT(html, HasSubstr("<h2>Beams (lbt)</h2>"));
  EXPECT_THAT(html, HasSubstr("Beams stopped before max_depth, by reason"));
  EXPECT_THAT(html, HasSubstr("beams: 12.8 MiB"));  // the beams among the memory owners
  expectNoEmptyChart(html);
  EXPECT_THAT(reportPage({{"s.json", stats()}}), Not(HasSubstr("Beams (lbt)")));
}

TEST_F(Report, AVolumeSectionShowsTrackingAndTheBrickCache) {
  json s = stats();
  s["volumes"] = {{"volumes", 1}, {"bricks", 96}, {"bytes", 524288}, {"collisions", 40}, {"transmittance_estimates", 300},
                  {"density_lookups", 9000}, {"brick_cells_walked", 2500}, {"time_s", {{"load", 0.1}, {"tracking", 0.4}, {"brick_reads", 0.05}}},
                  {"cache", {{"peak_bytes", 102400}, {"hits", 800}, {"bricks_loaded", 200}, {"evictions", 150}, {"hit_rate", 0.8}, {"bytes_read", 409600}}}};
  const std::string html = reportPage({{"s.json", s}});
  EXPECT_THAT(html, HasSubstr("<h2>Volumes</h2>"));
  EXPECT_THAT(html, HasSubstr("Brick cache (--volume-memory)"));
  EXPECT_THAT(html, HasSubstr("Hit rate 80 %"));
  expectNoEmptyChart(html);
  s["volumes"].erase("cache");  // no volume reads a file: no cache chart
  EXPECT_THAT(reportPage({{"s.json", s}}), Not(HasSubstr("Brick cache (--volume-memory)")));
  EXPECT_THAT(reportPage({{"s.json", stats()}}), Not(HasSubstr("<h2>Volumes</h2>")));
}

// Edges of every formula a page draws: zero times (ratios, bar scales), no generation, nothing
// diced, an RMSE of 0 on a log axis, one file compared with itself. No NaN or infinity may
// reach the page, and every chart that is drawn still has its marks.
TEST_F(Report, ZerosAndEmptyDataGiveFiniteCharts) {
  json s = stats();
  for (auto& [k, v] : s["totals"]["time_s"].items()) v = 0.0;
  s["generations"] = json::array();
  s["totals"]["leaves_diced"] = 0;
  s["totals"]["grid_cache_hits"] = 0;
  s["totals"]["rays_per_dicing"] = 0.0;
  s["totals"]["dicings_by_level"] = json::object();
  for (auto& [k, v] : s["memory"]["by_owner"].items()) v = 0;
  s["error_vs_time"] = {{{"spp", 1}, {"time_s", 0.0}, {"rmse", 0.0}}, {{"spp", 2}, {"time_s", 0.5}, {"rmse", 0.1}}};
  const std::regex nonFinite("[=>\" ,(-](nan|-?inf)\\b", std::regex::icase);
  for (const std::string& html : {reportPage({{"s.json", s}}), reportPage({{"a.json", s}, {"b.json", s}, {"c.json", s}}),
                                  comparisonPage({"a.json", s}, {"b.json", s})}) {
    std::smatch m;
    EXPECT_FALSE(std::regex_search(html, m, nonFinite)) << m.str() << " in " << html.substr(0, 200);
    expectNoEmptyChart(html);
  }
  EXPECT_THAT(reportPage({{"s.json", s}}), HasSubstr("No generation was traced."));
}

// Many files: the figures side by side, the one far from the others' median marked. Render
// times 1, 1.2, 0.9, 1.1 and 10 s: the median is 1.1 s, the median absolute deviation 0.1 s,
// so the bound is 3 · 1.4826 · 0.1 = 0.44 s from the median: 10 s is far outside, 0.9 s and
// 1.2 s (0.2 and 0.1 away) inside. The other figures are equal in every file: no spread, no
// outlier. Dicings of 960, 1001, 1000, 999, 1000: the MAD is 1, so 960 is 40 deviations out,
// but within 10 % of the median: not marked.
TEST_F(Report, AFrameSequenceMarksItsOutliers) {
  std::vector<StatsFile> runs;
  for (double t : {1.0, 1.2, 0.9, 1.1, 10.0}) {
    json s = stats();
    s["totals"]["time_s"]["total"] = t;
    s["totals"]["leaves_diced"] = std::vector<int>{960, 1001, 1000, 999, 1000}[runs.size()];
    runs.push_back({"frame-" + std::to_string(runs.size() + 1) + ".json", s});
  }
  const std::string html = reportPage(runs);
  EXPECT_THAT(html, HasSubstr("<h1>rayes report: 5 runs, pt (path tracing)</h1>"));
  EXPECT_EQ(occurrences(html, "<section class=\"run outlier\"><h1>frame-5.json"), 1u);
  EXPECT_EQ(occurrences(html, "<section class=\"run outlier\""), 1u);
  EXPECT_EQ(occurrences(html, "<section class=\"run\""), 4u);
  expectNoEmptyChart(html);
}

TEST_F(Report, AComparisonGivesRatiosBOverA) {
  json b = stats();
  b["totals"]["time_s"]["dice"] = 2 * stats()["totals"]["time_s"]["dice"].get<double>();
  b["memory"]["by_owner"]["film"] = 3 * stats()["memory"]["by_owner"]["film"].get<uint64_t>();
  const std::string html = comparisonPage({"a.json", stats()}, {"b.json", b});
  EXPECT_THAT(html, HasSubstr("<tr class=data><td>dice</td>"));
  const auto row = [&](const std::string& name, const std::string& table) {
    const size_t at = html.find("<tr class=data><td>" + name + "</td>", html.find("<h2>" + table + "</h2>"));
    return at == std::string::npos ? std::string() : html.substr(at, html.find("</tr>", at) - at);
  };
  EXPECT_THAT(row("dice", "Thread time, summed over threads (seconds)"), HasSubstr(">2&times;<"));
  EXPECT_THAT(row("film", "Memory by owner"), HasSubstr(">3&times;<"));
  EXPECT_THAT(row("rays", "Work: rays and dicings"), HasSubstr(">1&times;<"));
  EXPECT_THAT(html, HasSubstr("Final RMSE"));
  expectNoEmptyChart(html);
}

TEST_F(Report, RunsOfAnotherSceneOrResolutionAreNotCompared) {
  json other = stats();
  other["scene"]["resolution"] = {32, 24};
  try {
    checkComparable({"a.json", stats()}, {"b.json", other});
    FAIL() << "compared two resolutions";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "b.json");
    EXPECT_EQ(e.place(), "/scene/resolution");
    EXPECT_THAT(e.message(), HasSubstr("another resolution (32x24, not 16x12)"));
  }
  other = stats();
  other["scene"]["file"] = "/scenes/cornell-box.json";
  EXPECT_THROW(checkComparable({"a.json", stats()}, {"b.json", other}), InputError);
  other = stats();
  other["scene"]["file"] = "/elsewhere/teapot.json";  // the same scene from another checkout
  EXPECT_NO_THROW(checkComparable({"a.json", stats()}, {"b.json", other}));
}

TEST_F(Report, AStatsObjectIsCheckedFieldByField) {
  const auto placeOf = [](const json& s) -> std::string {
    try {
      checkStats(s, "s.json");
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "s.json");
      return e.place();
    }
    return "accepted";
  };
  EXPECT_EQ(placeOf(stats()), "accepted");
  json s = stats();
  s.erase("stats_version");
  EXPECT_EQ(placeOf(s), "/stats_version");
  s = stats();
  s["stats_version"] = kStatsVersion + 1;
  EXPECT_EQ(placeOf(s), "/stats_version");
  s = stats();
  s["totals"]["time_s"]["dice"] = "fast";
  EXPECT_EQ(placeOf(s), "/totals/time_s/dice");
  s = stats();
  s["generations"][0]["iterations"][0].erase("active_rays");
  EXPECT_EQ(placeOf(s), "/generations/0/iterations/0/active_rays");
  s = stats();
  s["totals"]["leaves_diced"] = -1;
  EXPECT_EQ(placeOf(s), "/totals/leaves_diced");
  s = stats();
  s["scene"]["resolution"] = {16};
  EXPECT_EQ(placeOf(s), "/scene/resolution");
  EXPECT_EQ(placeOf(json::array()), "");
}

// The command: one message naming the file and place, exit code 2, no page written.
struct BadStats {
  const char* name;
  std::string content;  // what the stats file holds; "<missing>": no file
  std::string message;
};

TEST_F(Report, BadStatsFilesAreRefusedWithNothingWritten) {
  json oldVersion = stats();
  oldVersion["stats_version"] = 0;
  const BadStats cases[] = {
      {"NotJson", "{\"scene\": ", "not JSON"},
      {"Empty", "", "the stats file is empty"},
      {"Blank", " \n", "the stats file is empty"},
      {"AnotherVersion", oldVersion.dump(), ":/stats_version: stats version 0, this rayes reads version 1"},
      {"NotAnObject", "[1, 2]", "the JSON is not an object"},
      {"Missing", "<missing>", "cannot open the stats file"},
  };
  for (const BadStats& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string in = path(std::string(c.name) + ".json");
    if (c.content != "<missing>") write(std::string(c.name) + ".json", c.content);
    const auto good = write("good.json", stats().dump());
    const auto r = testing::runRayes({"report", good, in, "-o", path("out/r.html"), "-q"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr(in));
    EXPECT_THAT(r.err, HasSubstr(c.message));
    EXPECT_EQ(occurrences(r.err, "\n"), 1u) << r.err;
    EXPECT_FALSE(fs::exists(path("out"))) << "a folder or page was left behind";
  }
}

TEST_F(Report, TheCommandWritesOnePageAndRefusesWhatItCannotDo) {
  const auto a = write("a.json", stats().dump());
  json other = stats();
  other["scene"]["resolution"] = {32, 24};
  const auto b = write("b.json", other.dump());
  auto r = testing::runRayes({"report", a, "-o", path("r.html"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(slurp(path("r.html")), HasSubstr("rayes report: pt (path tracing)"));
  r = testing::runRayes({"report", a, a, "-o", path("job.html"), "-q"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(slurp(path("job.html")), HasSubstr("rayes report: 2 runs"));
  r = testing::runRayes({"report", a, b, "--compare", "-o", path("cmp.html"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr(b + ":/scene/resolution: cannot compare it with " + a));
  EXPECT_FALSE(fs::exists(path("cmp.html")));
  r = testing::runRayes({"report", a, "--compare", "-o", path("cmp.html"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("--compare: compares two runs"));
  r = testing::runRayes({"report", a, "-o", path("r.txt"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr("name it NAME.html"));
  fs::create_directories(path("folder.html"));
  r = testing::runRayes({"report", a, "-o", path("folder.html"), "-q"});
  EXPECT_EQ(r.code, 2);
  EXPECT_THAT(r.err, HasSubstr(path("folder.html")));
  r = testing::runRayes({"report", a, "-o", a + ".html", "-q"});
  EXPECT_EQ(r.code, 0);
  r = testing::runRayes({"report", a, "-o", a, "-q"});  // refused: not .html, and would overwrite the input
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(json::parse(slurp(a)), stats());
}

}  // namespace
}  // namespace rayes
