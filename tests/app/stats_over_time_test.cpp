// Stats over time (app/renderer.h: GenerationTimes, MemorySample; docs/stats.md): every
// generation says when it began and where its time went, wall clock and thread time apart, and
// memory by owner is sampled after setup, after every generation and at the end.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "support/render_fixtures.h"
#include "support/temp_folder.h"

namespace rayes {
namespace {
using json = nlohmann::json;

json renderStats(testing::TempFolder& temp, const std::vector<std::string>& more) {
  std::vector<std::string> args = {"render", std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.json", "--res", "24x18",
                                   "--spp", "2", "-o", temp.path("t.png"), "--stats", temp.path("t.json"), "-q"};
  args.insert(args.end(), more.begin(), more.end());
  const auto r = testing::runRayes(args);
  EXPECT_EQ(r.code, 0) << r.err;
  return json::parse(temp.read("t.json"));
}

TEST(StatsOverTime, EveryGenerationSaysWhenItBeganAndWhereItsTimeWent) {
  testing::TempFolder temp;
  const json s = renderStats(temp, {"--ray-memory", "200K"});  // several batches
  ASSERT_GT(s["generations"].size(), 3u);
  double previousStart = 0;
  for (const json& g : s["generations"]) {
    const json& t = g["time_s"];
    for (const char* k : {"trace", "toplevel", "sort", "shade", "dice", "bottom", "leaf_queries"}) {
      ASSERT_TRUE(t.contains(k)) << k;
      EXPECT_GE(t[k].get<double>(), 0.0) << k;
    }
    // The top level and the sort are timed inside the trace, on the same clock.
    EXPECT_LE(t["toplevel"].get<double>() + t["sort"].get<double>(), t["trace"].get<double>());
    // Generations are traced one after the other.
    EXPECT_GE(g["start_s"].get<double>(), previousStart);
    previousStart = g["start_s"].get<double>() + t["trace"].get<double>();
  }
  EXPECT_LE(previousStart, s["totals"]["time_s"]["total"].get<double>());
}

TEST(StatsOverTime, MemoryIsSampledDuringTheRenderAndEndsAtTheOwnersFigures) {
  testing::TempFolder temp;
  const json s = renderStats(temp, {});
  const json& m = s["memory_over_time"];
  // After setup, after each generation, at the end.
  ASSERT_EQ(m.size(), s["generations"].size() + 2);
  double t = 0;
  for (const json& x : m) {
    EXPECT_GE(x["t_s"].get<double>(), t);
    t = x["t_s"].get<double>();
    EXPECT_GT(x["rss_bytes"].get<double>(), 0);
    EXPECT_LE(x["dice_cache"].get<double>(), s["memory"]["by_owner"]["dice_cache"].get<double>());
  }
  EXPECT_EQ(m.front()["film"], 0);  // not made yet after setup
  const json& last = m.back();
  for (const char* owner : {"film", "dice_buffers", "border_bounds", "ray_buffers", "candidates_and_sort"})
    EXPECT_EQ(last[owner], s["memory"]["by_owner"][owner]) << owner;
}

}  // namespace
}  // namespace rayes
