// `rayes report --watch DIR -o job.html` (app/report_watch.cpp): while a test writes a job's
// stats files into a folder one by one, the page is rewritten to hold each, reloads itself while
// the job runs, and stops reloading once --watch-until files were read. The waits below are
// bounds on how long the watch may take to notice (it looks every 0.05 s), not measurements.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <regex>
#include <thread>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
namespace fs = std::filesystem;

const std::string kScene = std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json";

int runsOnPage(const std::string& page) {
  std::smatch m;
  return std::regex_search(page, m, std::regex("id=watch-status data-done=[01]>Watching [^:]*: ([0-9]+) stats read"))
             ? std::stoi(m[1].str())
             : -1;
}

TEST(ReportWatch, RewritesThePageAsTheJobsStatsAppearAndStopsRefreshingAtTheEnd) {
  testing::TempFolder temp;
  for (const char* seed : {"1", "2"})
    ASSERT_EQ(testing::runRayes({"render", kScene, "--res", "16x12", "--spp", "1", "--seed", seed, "-o",
                                 temp.path(std::string("r") + seed + ".png"), "--stats",
                                 temp.path(std::string("r") + seed + ".json"), "-q"}).code, 0);
  fs::create_directories(temp.path("job"));
  const std::string page = temp.path("job.html");
  auto watch = std::async(std::launch::async, [&] {
    return testing::runRayes({"report", "--watch", temp.path("job"), "-o", page, "--watch-until", "2",
                              "--watch-interval", "0.05", "-q"}).code;
  });
  // Whatever happens below, the watch ends (a failed assertion must not leave it waiting): destroyed
  // before the future, whose destructor waits for the watch.
  struct EndWatch {
    std::string marker;
    ~EndWatch() { std::ofstream(marker) << ""; }
  } endWatch{temp.path("job/complete")};
  const auto waitFor = [&](int runs) {
    for (int i = 0; i < 600 && runsOnPage(temp.read("job.html")) != runs; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return temp.read("job.html");
  };
  // Before any stats: a waiting page that reloads.
  std::string now = waitFor(0);
  ASSERT_EQ(runsOnPage(now), 0) << now.substr(0, 600) << (watch.wait_for(std::chrono::seconds(0)) == std::future_status::ready ? " (the watch ended)" : "");
  EXPECT_NE(now.find("http-equiv=refresh"), std::string::npos);
  fs::copy_file(temp.path("r1.json"), temp.path("job/part-1.json"));
  now = waitFor(1);
  ASSERT_EQ(runsOnPage(now), 1);
  EXPECT_NE(now.find("http-equiv=refresh"), std::string::npos);
  EXPECT_NE(now.find("<h1>rayes report: pt (path tracing)</h1>"), std::string::npos);
  // A half-written file is skipped, not an error: the page keeps what it had.
  { std::ofstream(temp.path("job/part-2.json")) << "{\"stats_version\": 1, \"sce"; }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_EQ(runsOnPage(temp.read("job.html")), 1);
  fs::copy_file(temp.path("r2.json"), temp.path("job/part-2.json"), fs::copy_options::overwrite_existing);
  ASSERT_EQ(watch.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  EXPECT_EQ(watch.get(), 0);
  now = temp.read("job.html");
  EXPECT_EQ(runsOnPage(now), 2);
  EXPECT_EQ(now.find("http-equiv=refresh"), std::string::npos);  // complete: no more reloads
  EXPECT_NE(now.find("data-done=1"), std::string::npos);
  EXPECT_NE(now.find("2 runs"), std::string::npos);
  // No temporary is left beside the page.
  for (const auto& e : fs::directory_iterator(temp.dir())) EXPECT_EQ(e.path().filename().string().find(".job.html.tmp"), std::string::npos);
}

// A farm job's folder holds .film parts, whose headers hold the stats: the page is made from
// them, and the job is complete when every part 1..N is there.
TEST(ReportWatch, AFarmSplitsPartsMakeThePageAndEndTheWatchWhenAllAreThere) {
  testing::TempFolder temp;
  fs::create_directories(temp.path("parts"));
  for (const char* part : {"1", "2"})
    ASSERT_EQ(testing::runRayes({"render", kScene, "--res", "16x12", "--spp", "1", "--part", std::string(part) + "/2", "-o",
                                 temp.path(std::string("parts/part-") + part + ".film"), "-q"}).code, 0);
  EXPECT_EQ(testing::runRayes({"report", "--watch", temp.path("parts"), "-o", temp.path("job.html"), "-q"}).code, 0);
  const std::string page = temp.read("job.html");
  EXPECT_NE(page.find("2 of 2 parts; the job is complete"), std::string::npos);
  EXPECT_NE(page.find("2 runs"), std::string::npos);
  // And `rayes report` takes the parts as it takes stats files.
  EXPECT_EQ(testing::runRayes({"report", temp.path("parts/part-1.film"), temp.path("parts/part-2.film"), "-o",
                               temp.path("parts.html"), "-q"}).code, 0);
  EXPECT_NE(temp.read("parts.html").find("2 runs"), std::string::npos);
}

TEST(ReportWatch, AFileNamedCompleteEndsTheWatch) {
  testing::TempFolder temp;
  fs::create_directories(temp.path("job"));
  { std::ofstream(temp.path("job/complete")) << ""; }
  EXPECT_EQ(testing::runRayes({"report", "--watch", temp.path("job"), "-o", temp.path("j.html"), "-q"}).code, 0);
  EXPECT_NE(temp.read("j.html").find("the job is complete"), std::string::npos);
}

TEST(ReportWatch, RefusesWhatItCannotWatch) {
  testing::TempFolder temp;
  EXPECT_EQ(testing::runRayes({"report", "--watch", temp.path("none"), "-o", temp.path("j.html")}).code, 2);
  EXPECT_EQ(testing::runRayes({"report", "--watch", temp.dir().string(), "-o", temp.path("j.txt")}).code, 2);
  EXPECT_EQ(testing::runRayes({"report", "--watch", temp.dir().string(), "--watch-interval", "0", "-o", temp.path("j.html")}).code, 2);
  EXPECT_FALSE(fs::exists(temp.path("j.html")));
}

}  // namespace
}  // namespace rayes
