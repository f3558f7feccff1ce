// Progress (app/progress_state.h, app/progress.h): the render thread's hooks count the paths a
// batch has finished after a generation (paths whose ray slots are all Inactive), only when the
// reporter asked, and never backwards; `--progress json` prints one valid JSON object per line
// on standard output whose elapsed time, samples and paths never decrease, ending with phase
// "done" and every path counted. (How often the lines come is timing, not tested here.)
#include <sstream>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "app/progress_state.h"
#include "support/rayes_process.h"
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {

// A batch of `paths` paths of 2 slots each; path k is live when live[k].
RayBatch batchOf(const std::vector<bool>& live) {
  RayBatch b;
  b.timed = false;
  b.resize(2 * live.size() + 6);  // a batch array larger than the batch, as when the last batch is short
  for (size_t k = 0; k < live.size(); ++k)
    if (live[k]) b.ray[2 * k + (k % 2)].kind = k % 3 ? RayKind::Closest : RayKind::Shadow;
  for (size_t i = 2 * live.size(); i < b.size(); ++i) b.ray[i].kind = RayKind::Closest;  // beyond the batch
  return b;
}

TEST(Progress, FinishedPathsAreThoseWithNoRayWritten) {
  const RayBatch b = batchOf({true, false, false, true, true, false, true});
  EXPECT_EQ(finishedPaths(b, 2, 7), 3u);
  EXPECT_EQ(finishedPaths(b, 2, 3), 2u);  // only the batch's first paths
}

TEST(Progress, TheRenderThreadCountsOnlyWhenAskedAndNeverBackwards) {
  ProgressState s;
  s.pathsTotal = 100;
  s.batchDone(40, 100, 0);
  s.startBatch(7);
  const RayBatch some = batchOf({true, false, false, true, true, false, true});
  s.afterGeneration(0, some, 2);
  EXPECT_EQ(s.generation.load(), 0);
  EXPECT_EQ(s.paths(), 40u) << "not asked: no count";
  s.countWanted = true;
  s.afterGeneration(1, some, 2);
  EXPECT_EQ(s.paths(), 43u);
  EXPECT_FALSE(s.countWanted.load());
  // The next round of the same batch (lbt's beam ranges) starts its paths again.
  s.countWanted = true;
  s.afterGeneration(0, batchOf(std::vector<bool>(7, true)), 2);
  EXPECT_EQ(s.paths(), 43u);
  s.batchDone(47, 100, 1);
  EXPECT_EQ(s.paths(), 47u);
}

TEST(Progress, JsonLinesAreValidAndMonotoneAndEndDone) {
  const testing::TempFolder temp;
  const int w = 48, h = 36, spp = 4;
  const testing::ChildResult r = testing::runRayesProcess(
      {"render", testing::sourcePath("scenes/teapot.json"), "--res", std::to_string(w) + "x" + std::to_string(h),
       "--spp", std::to_string(spp), "--progressive", "--ray-memory", "1M", "--progress", "json", "-o",
       temp.path("o.exr")});
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<nlohmann::json> got;
  for (std::string line; std::getline(lines, line);) {
    ASSERT_NO_THROW(got.push_back(nlohmann::json::parse(line))) << line;
  }
  ASSERT_GE(got.size(), 1u) << r.out;
  const uint64_t total = uint64_t(w) * h * spp;
  for (size_t i = 0; i < got.size(); ++i) {
    const auto& j = got[i];
    for (const char* k : {"elapsed_s", "phase", "samples_done", "samples_total", "paths_done", "paths_total",
                          "generation", "eta_s", "rss_bytes"})
      ASSERT_TRUE(j.contains(k)) << k << " in " << j.dump();
    EXPECT_GT(j["rss_bytes"].get<uint64_t>(), 0u);
    EXPECT_TRUE(j["eta_s"].is_null() || j["eta_s"].get<double>() >= 0) << j.dump();
    EXPECT_LE(j["paths_done"].get<uint64_t>(), total);
    if (i == 0) continue;
    const auto& p = got[i - 1];
    for (const char* k : {"elapsed_s", "samples_done", "paths_done"})
      EXPECT_GE(j[k].get<double>(), p[k].get<double>()) << k << " decreased at line " << i;
  }
  const auto& last = got.back();
  EXPECT_EQ(last["phase"], "done");
  EXPECT_EQ(last["paths_done"].get<uint64_t>(), total);
  EXPECT_EQ(last["paths_total"].get<uint64_t>(), total);
  EXPECT_EQ(last["samples_done"].get<int>(), spp);
  EXPECT_EQ(last["samples_total"].get<int>(), spp);
  // The human messages stay on stderr; stdout is the JSON alone.
  EXPECT_THAT(r.err, ::testing::HasSubstr("rayes: wrote"));
}

TEST(Progress, QuietPrintsNoProgress) {
  const testing::TempFolder temp;
  const testing::ChildResult r = testing::runRayesProcess({"render", testing::sourcePath("scenes/teapot.json"), "--res",
                                                           "8x6", "--spp", "1", "--progress", "json", "-q", "-o",
                                                           temp.path("o.exr")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "");
}

}  // namespace
}  // namespace rayes
