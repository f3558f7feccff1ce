// Sub-leaves in whole renders (issue 33, item 2; rays/sub_leaf_runs.cpp): a leaf needed finer
// than --resident-lod is diced as sub-leaves into buffers of the resident level.
// - The image is the whole leaves' image: means within 4 standard errors over two seeds each
//   (the brief's bound), and, since the micro-triangles and the hits' bits are the same, the
//   same bytes at one seed.
// - It does not depend on the thread count.
// - With the grid cache, which keeps sub-leaf grids: the same bytes at any budget (none, one
//   that evicts sub-leaf grids, a large one) and thread count, and the same counts at 1 and 2
//   threads; every visit is a dicing or a cache hit.
// - A scene no ray needs finer than the resident level splits nothing and pays nothing: the
//   same bytes as with no resident level.
// - The memory floor falls: the dice buffers' bytes in the stats.
#include <cmath>
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {

Scene displacedTeapot(int w, int h, int spp, uint64_t seed) {
  Scene s = testing::resized(loadScene(testing::sourcePath("scenes/displaced-teapot.json")), w, h, spp);
  s.integrator.seed = seed;
  return s;
}

// Every ray at level 8 (--lod fixed): every run finer than a resident level of 6. No grid
// cache: every dicing goes through the dice buffers, whose bytes the floor test reads.
RenderOptions fixedAt8(int residentLod) {
  RenderOptions o;
  o.maxLod = 8;
  o.lod = LodRule::Fixed;
  o.residentLod = residentLod;
  o.gridCacheBytes = 0;
  return o;
}

TEST(SubLeafRender, SplitLeavesRenderTheWholeLeavesImage) {
  constexpr int kWidth = 40, kHeight = 30, kSpp = 8;
  const RenderOptions split = fixedAt8(6), whole = fixedAt8(12);
  RenderStats splitStats, wholeStats;
  const auto a1 = testing::renderBeauty(displacedTeapot(kWidth, kHeight, kSpp, 1), split, 2, &splitStats);
  const auto a2 = testing::renderBeauty(displacedTeapot(kWidth, kHeight, kSpp, 2), split, 2);
  const auto b3 = testing::renderBeauty(displacedTeapot(kWidth, kHeight, kSpp, 3), whole, 2, &wholeStats);
  const auto b4 = testing::renderBeauty(displacedTeapot(kWidth, kHeight, kSpp, 4), whole, 2);
  EXPECT_GT(testing::totalOf(splitStats, &GenerationStats::subLeafDicings), 0u);
  EXPECT_EQ(testing::totalOf(wholeStats, &GenerationStats::subLeafDicings), 0u);
  // Means of the green channel over two seeds each; the standard error of the difference of
  // the means from the per-pixel differences' spread (as tests/app/lod_rule_test.cpp).
  const size_t n = size_t(kWidth) * kHeight;
  double sum = 0, sumSq = 0, meanB = 0;
  for (size_t p = 0; p < n; ++p) {
    const double d = 0.5 * (a1[4 * p + 1] + a2[4 * p + 1]) - 0.5 * (b3[4 * p + 1] + b4[4 * p + 1]);
    sum += d;
    sumSq += d * d;
    meanB += 0.5 * (b3[4 * p + 1] + b4[4 * p + 1]) / double(n);
  }
  const double meanDiff = sum / double(n);
  const double standardError = std::sqrt((sumSq - double(n) * meanDiff * meanDiff) / double(n - 1) / double(n));
  ASSERT_GT(meanB, 0.0);
  EXPECT_LE(std::fabs(meanDiff), 4 * standardError) << "split mean - whole mean = " << meanDiff << ", SE " << standardError;
  // The same hits bit for bit (tests/rays/sub_leaf_runs_test.cpp), so the same image at one seed.
  EXPECT_EQ(testing::renderBeauty(displacedTeapot(kWidth, kHeight, kSpp, 1), whole, 2), a1);
  // The floor: one level-6 buffer per thread instead of level 8.
  EXPECT_GT(splitStats.memory.diceBuffers, 0u);
  EXPECT_GT(double(wholeStats.memory.diceBuffers), 8.0 * double(splitStats.memory.diceBuffers))
      << wholeStats.memory.diceBuffers << " against " << splitStats.memory.diceBuffers;
}

TEST(SubLeafRender, SplitImageDoesNotDependOnThreads) {
  const Scene s = displacedTeapot(24, 18, 2, 5);
  const RenderOptions split = fixedAt8(6);
  EXPECT_EQ(testing::renderBeauty(s, split, 1), testing::renderBeauty(s, split, 2));
}

TEST(SubLeafRender, SubLeafGridsInTheGridCacheRenderTheSameImage) {
  const Scene s = displacedTeapot(24, 18, 2, 7);
  const auto whole = testing::renderBeauty(s, fixedAt8(12), 2);
  struct Run {
    size_t cacheBytes;
    int threads;
    RenderStats stats;
  };
  Run runs[] = {{0, 2, {}}, {size_t(1) << 20, 1, {}}, {size_t(1) << 20, 2, {}}, {size_t(256) << 20, 2, {}}};
  for (Run& r : runs) {
    RenderOptions o = fixedAt8(6);
    o.gridCacheBytes = r.cacheBytes;
    EXPECT_EQ(testing::renderBeauty(s, o, r.threads, &r.stats), whole) << r.cacheBytes << " bytes, " << r.threads;
  }
  auto total = [](const Run& r, uint64_t GenerationStats::*counter) { return testing::totalOf(r.stats, counter); };
  const Run &off = runs[0], &smallOne = runs[1], &smallTwo = runs[2], &large = runs[3];
  for (const Run* r : {&smallOne, &smallTwo, &large})
    EXPECT_EQ(total(*r, &GenerationStats::leavesDiced) + total(*r, &GenerationStats::gridCacheHits),
              total(off, &GenerationStats::leavesDiced));
  EXPECT_EQ(total(off, &GenerationStats::subLeafCacheHits), 0u);
  EXPECT_GT(total(large, &GenerationStats::subLeafCacheHits), total(smallTwo, &GenerationStats::subLeafCacheHits));
  EXPECT_LT(total(large, &GenerationStats::subLeafDicings), total(off, &GenerationStats::subLeafDicings));
  for (uint64_t GenerationStats::*counter : {&GenerationStats::leavesDiced, &GenerationStats::subLeafDicings,
                                             &GenerationStats::subLeafCacheHits, &GenerationStats::gridCacheHits})
    EXPECT_EQ(total(smallOne, counter), total(smallTwo, counter));
  EXPECT_LE(smallTwo.stats.memory.diceCache, size_t(1) << 20);
}

TEST(SubLeafRender, ASceneNeverFinerThanTheResidentLevelSplitsNothing) {
  const Scene s = testing::smallTeapot(32, 24, 2);
  RenderOptions resident, none;
  resident.maxLod = none.maxLod = 8;
  resident.residentLod = 7;
  none.residentLod = 12;
  resident.lodBias = none.lodBias = -2;  // every ray at most level 6 here
  RenderStats stats;
  const auto image = testing::renderBeauty(s, resident, 2, &stats);
  EXPECT_EQ(testing::totalOf(stats, &GenerationStats::splitRuns), 0u);
  EXPECT_EQ(testing::renderBeauty(s, none, 2), image);
}

}  // namespace
}  // namespace rayes
