// --grid-cache BYTES (rays/grid_cache.h): the sorted pipeline keeps diced grids across the
// iterations and generations of a render. The image is the same bits with the cache off, too
// small for most grids (evicted and diced again) or large, on 1 or 2 threads; every leaf visit is
// either a dicing or a cache hit, so dicings fall by exactly the hits; and the counts do not
// depend on the thread count (the cache is asked serially, in run order).
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {
using testing::smallTeapot;

struct CachedRender {
  std::vector<float> image;
  uint64_t dicings = 0, hits = 0;
  size_t cacheBytes = 0;
};

CachedRender renderWithGridCache(const Scene& scene, size_t bytes, int threads) {
  RenderOptions o;
  o.gridCacheBytes = bytes;
  RenderStats stats;
  CachedRender out;
  out.image = testing::renderBeauty(scene, o, threads, &stats);
  for (const auto& g : stats.generations) {
    out.dicings += g.stats.leavesDiced;
    out.hits += g.stats.gridCacheHits;
  }
  out.cacheBytes = stats.memory.diceCache;
  return out;
}

TEST(GridCacheRender, ImageIsTheSameWithAnyBudgetAndDicingsFallByTheHits) {
  const Scene scene = smallTeapot(24, 18, 2);
  const CachedRender off = renderWithGridCache(scene, 0, 2);
  const size_t tiny = 64 << 10, large = 256 << 20;
  const CachedRender small = renderWithGridCache(scene, tiny, 2);
  const CachedRender big = renderWithGridCache(scene, large, 2);
  const CachedRender bigOneThread = renderWithGridCache(scene, large, 1);
  EXPECT_EQ(small.image, off.image);
  EXPECT_EQ(big.image, off.image);
  EXPECT_EQ(bigOneThread.image, off.image);

  EXPECT_EQ(off.hits, 0u);
  EXPECT_EQ(off.cacheBytes, 0u);
  for (const CachedRender* r : {&small, &big}) EXPECT_EQ(r->dicings + r->hits, off.dicings);  // static leaves
  EXPECT_GT(big.hits, 0u);
  EXPECT_GT(big.hits, small.hits);
  EXPECT_LE(small.cacheBytes, tiny);
  EXPECT_LE(big.cacheBytes, large);
  EXPECT_EQ(bigOneThread.dicings, big.dicings);
  EXPECT_EQ(bigOneThread.hits, big.hits);
}

// --candidates-per-ray: how many leaves a ray gets per iteration changes the iterations and the
// dicings, never the image (the kept hit is the minimum of one total order, sorted_engine.h).
TEST(GridCacheRender, ImageIsTheSameForAnyCandidatesPerRay) {
  const Scene scene = smallTeapot(24, 18, 2);
  std::vector<float> images[3];
  size_t iterations[3] = {};
  const int perRay[3] = {1, 4, 100};
  for (int k = 0; k < 3; ++k) {
    RenderOptions o;
    o.candidatesPerRay = perRay[k];
    RenderStats stats;
    images[k] = testing::renderBeauty(scene, o, 2, &stats);
    for (const auto& g : stats.generations) iterations[k] += g.stats.iterations.size();
  }
  EXPECT_EQ(images[0], images[2]);
  EXPECT_EQ(images[1], images[2]);
  EXPECT_GT(iterations[0], iterations[2]);  // the clip did act
}

}  // namespace
}  // namespace rayes
