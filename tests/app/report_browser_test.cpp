// The report pages in a real browser: headless Chromium (Debian's `chromium`, scripts/setup)
// opens a single-render page, a frame sequence's page and a comparison, runs their script, and
// dumps the DOM. The page's own check (app/report_page.cpp) records every script error and
// every chart without a drawn mark in #page-check; a page that fails it, or whose check never
// ran, fails here. Skipped with a message when chromium is absent, unless
// RAYES_REQUIRE_CHROMIUM is set (as CI should), when its absence fails.
// `ctest -L browser` runs these alone (their label, CMakeLists.txt).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <gtest/gtest.h>
#include <gmock/gmock.h>
#include "support/exr_image.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

std::string chromiumPath() {
  for (const char* p : {"/usr/bin/chromium", "/usr/lib/chromium/chromium"})
    if (fs::exists(p)) return p;
  return "";
}

// The DOM after the page's load event, as Chromium serialises it.
std::string dumpDom(const std::string& chromium, const std::string& page, const std::string& profile) {
  const std::string command = chromium + " --headless --disable-gpu --no-sandbox --no-first-run --user-data-dir=" + profile +
                              " --virtual-time-budget=5000 --dump-dom file://" + page + " 2>" + profile + ".log";
  std::string dom;
  if (FILE* f = ::popen(command.c_str(), "r")) {
    char buf[65536];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) dom.append(buf, n);
    ::pclose(f);
  }
  return dom;
}

std::string attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  return std::regex_search(element, m, std::regex(name + "=\"([^\"]*)\"")) ? m[1].str() : std::string("<absent>");
}

class ReportBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = chromiumPath();
    if (chromium_.empty()) {
      if (std::getenv("RAYES_REQUIRE_CHROMIUM")) FAIL() << "chromium is not installed and RAYES_REQUIRE_CHROMIUM is set";
      GTEST_SKIP() << "chromium is not installed (scripts/setup installs Debian's chromium): the report pages were not "
                      "opened in a browser";
    }
  }
  std::string path(const std::string& n) const { return temp_.path(n); }
  void render(const std::string& stats, const std::vector<std::string>& more) {
    std::vector<std::string> args = {"render", kScene, "--res", "24x18", "-o", path(stats + ".exr"), "--stats", path(stats), "-q"};
    args.insert(args.end(), more.begin(), more.end());
    const auto r = testing::runRayes(args);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  // Opens the page and expects its check to have run and passed; returns the chart count.
  int expectPagePasses(const std::string& page) {
    const std::string dom = dumpDom(chromium_, page, path("profile"));
    std::smatch m;
    if (!std::regex_search(dom, m, std::regex("<div id=\"page-check\"[^>]*>"))) {
      ADD_FAILURE() << page << ": the page's check did not run (a script error before it, or no load event); DOM of "
                    << dom.size() << " bytes; chromium said: " << temp_.read("profile.log").substr(0, 2000);
      return 0;
    }
    const std::string check = m[0].str();
    EXPECT_EQ(attribute(check, "data-status"), "ok")
        << page << ": script errors: " << attribute(check, "data-errors") << "; empty charts: " << attribute(check, "data-empty");
    return std::atoi(attribute(check, "data-charts").c_str());
  }
  std::string chromium_;
  testing::TempFolder temp_;
};

TEST_F(ReportBrowser, ASingleRenderAJobAndAComparisonOpenWithEveryChartDrawn) {
  render("ref.json", {"--spp", "8"});
  render("a.json", {"--spp", "4", "--seed", "2", "--reference", path("ref.json.exr"), "--report", path("single.html")});
  render("b.json", {"--spp", "4", "--seed", "3", "--reference", path("ref.json.exr"), "--grid-cache", "0"});
  ASSERT_EQ(testing::runRayes({"report", path("a.json"), path("b.json"), path("ref.json"), "-o", path("job.html"), "-q"}).code, 0);
  ASSERT_EQ(testing::runRayes({"report", path("a.json"), path("b.json"), "--compare", "-o", path("cmp.html"), "-q"}).code, 0);
  // The single page: time (2), generations (6), level of detail, grid cache, memory, error.
  EXPECT_GE(expectPagePasses(path("single.html")), 10);
  EXPECT_GE(expectPagePasses(path("job.html")), 3 * 9 + 7);
  EXPECT_GE(expectPagePasses(path("cmp.html")), 5);
}

// The heat maps: a mousemove over a known pixel (the page's #probe=LAYER,X,Y dispatches it as the
// cursor would) makes every read-out show its layer's value there. The value read back is the
// EXR's float printed to 6 significant digits: within half a unit of the 6th digit.
TEST_F(ReportBrowser, TheHeatMapsReadOutTheValueUnderTheCursor) {
  render("cost.json", {"--spp", "2", "--cost-layers", "--report", path("rendered.html")});
  ASSERT_EQ(testing::runRayes({"report", path("cost.json"), "-o", path("reported.html"), "-q"}).code, 0);
  const testing::ExrImage im = testing::readExrImage(path("cost.json.exr"));
  const std::vector<float>& d = im.channels.at("dicings.Y");
  const size_t at = size_t(std::max_element(d.begin(), d.end()) - d.begin());
  const int x = int(at % size_t(im.width)), y = int(at / size_t(im.width));
  ASSERT_GT(d[at], 0);
  for (const char* page : {"rendered.html", "reported.html"}) {
    EXPECT_GE(expectPagePasses(path(page)), 10) << page;
    const std::string dom = dumpDom(chromium_, path(page) + "#probe=dicings," + std::to_string(x) + "," + std::to_string(y),
                                    path("profile"));
    for (const auto& [layer, channel] : {std::pair<std::string, std::string>{"dicings", "dicings.Y"}, {"time", "time.Y"}}) {
      std::smatch m;
      const std::regex readout("<div class=\"pixel-readout\" data-layer=\"" + layer + "\">x ([0-9]+), y ([0-9]+): ([-0-9.e+]+)");
      ASSERT_TRUE(std::regex_search(dom, m, readout)) << page << ": no read-out of " << layer;
      EXPECT_EQ(std::stoi(m[1].str()), x);
      EXPECT_EQ(std::stoi(m[2].str()), y);
      const double shown = std::stod(m[3].str()), value = im.at(channel, x, y);
      EXPECT_NEAR(shown, value, 5e-6 * std::fabs(value)) << page << " " << layer;
    }
  }
}

// The check itself: a page with a script error, or with a chart that draws nothing, fails.
TEST_F(ReportBrowser, ThePagesCheckCatchesAScriptErrorAndAnEmptyChart) {
  ASSERT_EQ(testing::runRayes({"render", kScene, "--spp", "1", "--res", "8x6", "-o", path("t.png"), "--report",
                               path("r.html"), "-q"}).code, 0);
  const std::string html = temp_.read("r.html");
  const std::string broken = std::regex_replace(html, std::regex("</body>"), "<script>undefinedFunction();</script>"
                                                "<figure><svg class=chart width=10 height=10></svg></figure></body>");
  std::ofstream(path("broken.html")) << broken;
  const std::string dom = dumpDom(chromium_, path("broken.html"), path("profile"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex("<div id=\"page-check\"[^>]*>"))) << dom.size();
  EXPECT_EQ(attribute(m[0].str(), "data-status"), "fail");
  EXPECT_THAT(attribute(m[0].str(), "data-errors"), ::testing::HasSubstr("undefinedFunction"));
  EXPECT_NE(attribute(m[0].str(), "data-empty"), "");
}

}  // namespace
}  // namespace rayes
