// --dice-cache K (issue 10, item 3; the thesis's Table 6.2): rays traced one at a time through an
// LRU cache of diced grids find exactly the SortedEngine's hits, so the image is the sorted pipeline's
// bit for bit, whatever K; only the number of dicings changes with K, and it is a function of
// (scene, settings, K) alone.
#include <gtest/gtest.h>
#include "support/render_fixtures.h"

namespace rayes {
namespace {
using testing::renderBeauty;
using testing::smallTeapot;

struct CachedRender {
  std::vector<float> image;
  EngineStats engine;
  uint64_t dicings = 0, micropolygons = 0;
};

CachedRender renderCached(const Scene& scene, size_t entries, int threads) {
  ThreadLimit limit(threads);
  RenderOptions o;
  o.diceCacheEntries = entries;
  Renderer r(scene, o);
  CachedRender out;
  out.image = r.render().beautyRgba();
  out.engine = r.stats().engine;
  for (const auto& g : r.stats().generations) {
    out.dicings += g.stats.leavesDiced;
    out.micropolygons += g.stats.micropolygonsCreated;
  }
  return out;
}

class DiceCache : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(smallTeapot(24, 18, 2));
    reference_ = new std::vector<float>(renderBeauty(*scene_, RenderOptions{}, 2));
  }
  static void TearDownTestSuite() { delete scene_; delete reference_; }
  static Scene* scene_;
  static std::vector<float>* reference_;
};
Scene* DiceCache::scene_ = nullptr;
std::vector<float>* DiceCache::reference_ = nullptr;

TEST_F(DiceCache, ImageEqualsTheSortedPipelineForAnyCacheSize) {
  for (size_t k : {size_t(1), size_t(4), size_t(1000)}) EXPECT_EQ(renderCached(*scene_, k, 2).image, *reference_) << k;
}

// Every grid request is a hit or a miss, and which grids the rays ask for (leaf, time interval,
// level) does not depend on the cache: hits + misses is the same for every K, and a larger cache
// can only turn misses into hits (LRU is a stack algorithm: a K-entry cache's content is always
// part of a larger one's). Every miss is one dicing.
TEST_F(DiceCache, MissesAreDicingsAndFallAsTheCacheGrows) {
  const CachedRender one = renderCached(*scene_, 1, 2), some = renderCached(*scene_, 8, 2),
                     all = renderCached(*scene_, 1000, 2);
  for (const CachedRender* r : {&one, &some, &all}) {
    EXPECT_EQ(r->engine.cacheMisses, r->dicings);
    EXPECT_EQ(r->engine.cacheHits + r->engine.cacheMisses, one.engine.cacheHits + one.engine.cacheMisses);
    EXPECT_GT(r->micropolygons, 0u);
  }
  EXPECT_EQ(one.engine.cacheEntries, 1u);
  EXPECT_EQ(all.engine.cacheEntries, 1000u);
  EXPECT_LE(all.dicings, some.dicings);
  EXPECT_LT(some.dicings, one.dicings);
  // The teapot has 32 patches: with room for all of them, a leaf is diced again only when a ray
  // needs it finer than it is held, at most once per level above its first.
  EXPECT_LE(all.dicings, uint64_t(scene_->leaves.size()) * (RenderOptions{}.maxLod + 1));
  EXPECT_GT(all.engine.cachePeakBytes, 0u);
}

TEST_F(DiceCache, CountsDoNotDependOnThreadCount) {
  const CachedRender a = renderCached(*scene_, 8, 1), b = renderCached(*scene_, 8, 2);
  EXPECT_EQ(a.image, b.image);
  EXPECT_EQ(a.engine.cacheHits, b.engine.cacheHits);
  EXPECT_EQ(a.engine.cacheMisses, b.engine.cacheMisses);
}

// A generated leaf's patch exists only while it is diced: a grid the cache keeps must keep its
// patch (its border regions read it on later hits). forest-1's bark is displaced and curved, so
// a dangling patch would be read by the second ray that reuses a grid.
TEST(DiceCacheOnGeneratedLeaves, ImageEqualsTheSortedPipeline) {
  Scene scene = loadScene(testing::sourcePath("scenes/forest-1.json"));
  scene.width = 32;
  scene.height = 16;
  scene.samplesPerPixel = 1;
  const std::vector<float> sorted = renderBeauty(scene, RenderOptions{}, 2);
  for (size_t k : {size_t(2), size_t(64)}) EXPECT_EQ(renderCached(scene, k, 2).image, sorted) << k;
}

}  // namespace
}  // namespace rayes
