// Runs finer than the resident level (rays/sub_leaf_runs.cpp, issue 33 item 2): the leaf is
// diced as sub-leaves into a buffer of the resident level only. What could go wrong:
// - a hit differs from the whole leaf's (a sub-leaf's vertex, parameter, quad number or
//   crack-closing region not the whole leaf's): every hit is compared bit for bit with the same
//   rays traced with no split, on a displaced teapot (curved, border regions everywhere) with
//   each ray at its own level on each leaf, coarse and fine rays in one run;
// - the sub-leaves diced depend on thread timing: counts and hits at 1 and 2 threads;
// - the memory floor does not fall: the dice buffers' bytes;
// - a sub-leaf grid kept in the grid cache (rays/grid_cache.h) serves a later run wrongly, or
//   is not served at all: the same rays traced again take every sub-leaf from the cache, with
//   the same hits; evicted and diced again under a small budget, still the same hits, and the
//   cache's counts the same at 1 and 2 threads; every visit is a dicing or a hit.
// (Rays aimed at the seams between sub-leaves are in tests/dicing/watertight_test.cpp; the same
// image at the render level in tests/app/sub_leaf_render_test.cpp.)
#include <gtest/gtest.h>
#include <cstring>
#include <limits>
#include <tbb/task_arena.h>
#include "core/rng.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "rays/run_chunks.h"
#include "rays/sorted_engine.h"
#include "rays/teapot_on_floor.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kMaxLod = 9;

// The teapot's patches displaced by noise, on the floor.
test::TracedWorld displacedTeapot() {
  std::vector<PatchPtr> leaves = test::teapotOnFloor();
  NoiseParams noise;
  noise.amplitude = 0.04f;
  noise.frequency = 4.0f;
  noise.octaves = 3;
  const auto d = std::make_shared<NoiseDisplacement>(noise);
  for (size_t k = 0; k < 32; ++k) leaves[k] = std::make_shared<DisplacedPatch>(leaves[k], d);
  return test::TracedWorld(std::move(leaves));
}

RayBatch raysAtTheTeapot(int n, bool shadow) { return test::raysAtTheTeapot(n, shadow, 23); }

struct Traced {
  RayBatch batch;
  GenerationStats stats;
  size_t diceBufferBytes = 0;
};

// Each (ray, leaf) at a level of its own, 0..kMaxLod (a hash of the pair), so a leaf's run
// mixes rays coarser and finer than the resident level.
TraceSettings settings(int residentLod, size_t gridCacheBytes) {
  TraceSettings s;
  s.maxLod = kMaxLod;
  s.residentLod = residentLod;
  s.gridCacheBytes = gridCacheBytes;
  s.levelHook = [](uint32_t ray, uint32_t leaf, int) {
    return int((ray * 2654435761u ^ leaf * 40503u) >> 7) % (kMaxLod + 1);
  };
  return s;
}

Traced traceWith(SortedEngine& engine, bool shadow, int threads, int rays = 4000) {
  Traced out;
  out.batch = raysAtTheTeapot(rays, shadow);
  TraceTimes times;
  tbb::task_arena(threads).execute([&] { engine.trace(out.batch, out.stats, times); });
  out.diceBufferBytes = engine.diceBufferBytes();
  return out;
}

Traced trace(const test::TracedWorld& w, int residentLod, bool shadow, int threads, size_t gridCacheBytes = 0) {
  SortedEngine engine(w.top, w.source, settings(residentLod, gridCacheBytes));
  return traceWith(engine, shadow, threads);
}

void expectSameHits(const Traced& a, const Traced& b) {
  int hits = 0;
  for (uint32_t i = 0; i < a.batch.size(); ++i) {
    const RayHit &x = a.batch.hit[i], &y = b.batch.hit[i];
    ASSERT_EQ(x.leaf, y.leaf) << "ray " << i;
    if (!x.valid()) continue;
    ++hits;
    ASSERT_EQ(std::memcmp(&x, &y, sizeof x), 0) << "ray " << i << ": t " << x.t << " / " << y.t << ", quad " << x.quad
                                                << " / " << y.quad << ", u " << x.u << " / " << y.u;
  }
  EXPECT_GT(hits, int(a.batch.size()) / 4);
}

TEST(SubLeafRuns, SplitRunsFindTheWholeLeafsHitsBitForBit) {
  const auto w = displacedTeapot();
  const Traced whole = trace(w, kMaxLod, false, 2), split = trace(w, 6, false, 2);
  EXPECT_EQ(whole.stats.splitRuns, 0u);
  EXPECT_GT(split.stats.splitRuns, 0u);
  EXPECT_GT(split.stats.subLeafDicings, 0u);
  for (size_t m = 7; m < GenerationStats::kLevels; ++m) EXPECT_EQ(split.stats.dicingsByLevel[m], 0u) << m;
  expectSameHits(whole, split);
  // With the grid cache, large or evicting sub-leaf grids: still the same hits.
  expectSameHits(whole, trace(w, 6, false, 2, size_t(256) << 20));
  expectSameHits(whole, trace(w, 6, false, 2, size_t(1) << 20));
}

TEST(SubLeafRuns, SplitShadowRaysAreOccludedExactlyAsWhole) {
  const auto w = displacedTeapot();
  const Traced whole = trace(w, kMaxLod, true, 2), split = trace(w, 6, true, 2);
  int occluded = 0;
  for (uint32_t i = 0; i < whole.batch.size(); ++i) {
    ASSERT_EQ(whole.batch.hit[i].valid(), split.batch.hit[i].valid()) << "ray " << i;
    occluded += whole.batch.hit[i].valid();
  }
  EXPECT_GT(occluded, 100);
}

TEST(SubLeafRuns, SameHitsAndDicingsAtOneAndTwoThreads) {
  const auto w = displacedTeapot();
  const Traced one = trace(w, 6, false, 1), two = trace(w, 6, false, 2);
  expectSameHits(one, two);
  EXPECT_EQ(one.stats.leavesDiced, two.stats.leavesDiced);
  EXPECT_EQ(one.stats.subLeafDicings, two.stats.subLeafDicings);
  EXPECT_EQ(one.stats.dicingsByLevel, two.stats.dicingsByLevel);
}

// The same rays traced twice by one engine (two generations of a batch, say): the first trace
// as `first`, the second as `again`. Fewer rays than above: every grid they need, the whole
// leaves' and the sub-leaves', fits in the large budget.
struct TracedTwice {
  Traced first, again;
};
TracedTwice traceTwice(const test::TracedWorld& w, int threads, size_t gridCacheBytes) {
  SortedEngine engine(w.top, w.source, settings(6, gridCacheBytes));
  TracedTwice out;
  out.first = traceWith(engine, false, threads, 1000);
  out.again = traceWith(engine, false, threads, 1000);
  return out;
}

TEST(SubLeafRuns, SubLeafGridsAreCacheHitsWhenTheSameRaysComeAgain) {
  const auto w = displacedTeapot();
  SortedEngine wholeEngine(w.top, w.source, settings(kMaxLod, 0));
  const Traced whole = traceWith(wholeEngine, false, 2, 1000);
  const TracedTwice t = traceTwice(w, 2, size_t(1) << 30);
  ASSERT_GT(t.first.stats.subLeafDicings, 0u);
  // The same runs and plans: every grid is in the cache, the whole leaves' and the sub-leaves'.
  EXPECT_EQ(t.again.stats.leavesDiced, 0u);
  EXPECT_EQ(t.again.stats.subLeafDicings, 0u);
  EXPECT_EQ(t.again.stats.subLeafCacheHits, t.first.stats.subLeafDicings + t.first.stats.subLeafCacheHits);
  EXPECT_EQ(t.again.stats.gridCacheHits, t.first.stats.leavesDiced + t.first.stats.gridCacheHits);
  expectSameHits(whole, t.first);
  expectSameHits(whole, t.again);
}

TEST(SubLeafRuns, EvictedSubLeafGridsAreDicedAgainTheSameAtAnyThreadCount) {
  const auto w = displacedTeapot();
  SortedEngine uncachedEngine(w.top, w.source, settings(6, 0));
  const Traced uncached = traceWith(uncachedEngine, false, 2, 1000);
  const size_t small = size_t(4) << 20;  // 16 level-6 grids
  const TracedTwice one = traceTwice(w, 1, small), two = traceTwice(w, 2, small);
  const TracedTwice large = traceTwice(w, 2, size_t(1) << 30);
  for (const TracedTwice* t : {&one, &two, &large})
    for (const Traced* trace : {&t->first, &t->again}) {
      expectSameHits(uncached, *trace);
      // A sub-leaf a run reaches is diced or taken from the cache: never both, never neither.
      EXPECT_EQ(trace->stats.leavesDiced + trace->stats.gridCacheHits, uncached.stats.leavesDiced);
      EXPECT_EQ(trace->stats.splitRuns, uncached.stats.splitRuns);
    }
  // The small cache evicted sub-leaf grids before the rays came again, but kept some.
  EXPECT_GT(one.again.stats.subLeafCacheHits, 0u);
  EXPECT_GT(one.again.stats.subLeafDicings, 0u);
  EXPECT_GT(large.again.stats.subLeafCacheHits, one.again.stats.subLeafCacheHits);
  for (const auto member : {&TracedTwice::first, &TracedTwice::again}) {
    const GenerationStats &a = (one.*member).stats, &b = (two.*member).stats;
    EXPECT_EQ(a.leavesDiced, b.leavesDiced);
    EXPECT_EQ(a.subLeafDicings, b.subLeafDicings);
    EXPECT_EQ(a.subLeafCacheHits, b.subLeafCacheHits);
    EXPECT_EQ(a.gridCacheHits, b.gridCacheHits);
    EXPECT_EQ(a.dicingsByLevel, b.dicingsByLevel);
  }
}

// A close-up leaf: one displaced quad, every ray in one run, half of them finer than the
// resident level. The run is longer than several chunks (rays/run_chunks.h) and so is each
// sub-leaf's share of its fine rays, so its plan and its intersections run in chunks that
// either thread may take; what could go wrong there is a hit or a dicing decided by which
// thread took which chunk.
struct CloseUp {
  static constexpr int kRays = 24000;
  test::TracedWorld world;
  CloseUp() : world(leaves()) {}
  static std::vector<PatchPtr> leaves() {
    NoiseParams noise;
    noise.amplitude = 0.05f;
    noise.frequency = 3.0f;
    noise.octaves = 3;
    const auto quad = std::make_shared<BilinearPatch>(Vec3{-1, -1, 0}, Vec3{1, -1, 0}, Vec3{-1, 1, 0}, Vec3{1, 1, 0});
    return {std::make_shared<DisplacedPatch>(quad, std::make_shared<NoiseDisplacement>(noise))};
  }
  // Odd rays at kMaxLod (above a resident level of kMaxLod - 1: 4 sub-leaves), even rays at
  // 0..6 (coarse: the whole leaf).
  static int level(uint32_t ray) { return ray % 2 ? kMaxLod : int((ray * 2654435761u) >> 9) % 7; }
  Traced trace(int residentLod, size_t gridCacheBytes, bool shadow, int threads) const {
    TraceSettings s;
    s.maxLod = kMaxLod;
    s.residentLod = residentLod;
    s.gridCacheBytes = gridCacheBytes;
    s.levelHook = [](uint32_t ray, uint32_t, int) { return level(ray); };
    SortedEngine engine(world.top, world.source, s);
    Traced out;
    out.batch.resize(kRays);
    for (int i = 0; i < kRays; ++i) {
      const RngKey k{uint32_t(i), shadow ? 1u : 0u, 0, 41};
      const Vec3 o{-0.5f + sampleUniform(k, 0), -0.5f + sampleUniform(k, 1), 2.0f};
      const Vec3 target{-0.95f + 1.9f * sampleUniform(k, 2), -0.95f + 1.9f * sampleUniform(k, 3), 0.0f};
      out.batch.setFromNowhere(size_t(i), shadow ? RayKind::Shadow : RayKind::Closest, o, normalize(target - o),
                               shadow ? 3.0f : kInf, 0.0f, 0.0f);
    }
    TraceTimes times;
    tbb::task_arena(threads).execute([&] { engine.trace(out.batch, out.stats, times); });
    return out;
  }
};

TEST(SubLeafRuns, ACloseUpRunInChunksFindsTheWholeLeafsHitsAtAnyThreadCount) {
  static_assert(CloseUp::kRays / 2 / 4 > 2 * kRunChunk, "each sub-leaf's fine rays span several chunks");
  const CloseUp c;
  for (const size_t cache : {size_t(0), size_t(256) << 20}) {
    const Traced whole = c.trace(kMaxLod, cache, false, 2);
    const Traced one = c.trace(kMaxLod - 1, cache, false, 1), two = c.trace(kMaxLod - 1, cache, false, 2);
    EXPECT_EQ(whole.stats.splitRuns, 0u);
    EXPECT_GT(two.stats.splitRuns, 0u);
    EXPECT_EQ(two.stats.subLeafDicings, 4u) << "cache " << cache;  // the first run reaches all four
    expectSameHits(whole, one);
    expectSameHits(whole, two);
    EXPECT_EQ(one.stats.leavesDiced, two.stats.leavesDiced);
    EXPECT_EQ(one.stats.subLeafDicings, two.stats.subLeafDicings);
    EXPECT_EQ(one.stats.dicingsByLevel, two.stats.dicingsByLevel);
    // Shadow rays: the first occluder in a chunk ends the ray's search in later sub-leaves.
    const Traced wholeShadow = c.trace(kMaxLod, cache, true, 2), splitShadow = c.trace(kMaxLod - 1, cache, true, 2);
    int occluded = 0;
    for (uint32_t i = 0; i < wholeShadow.batch.size(); ++i) {
      ASSERT_EQ(wholeShadow.batch.occluded(i), splitShadow.batch.occluded(i)) << "ray " << i;
      occluded += wholeShadow.batch.occluded(i);
    }
    EXPECT_GT(occluded, CloseUp::kRays / 2);
  }
}

TEST(SubLeafRuns, TheDiceBuffersHoldOnlyTheResidentLevel) {
  const auto w = displacedTeapot();
  const Traced whole = trace(w, kMaxLod, false, 1), split = trace(w, 6, false, 1);
  DiceBuffer six(6), nine(9);
  six.dice(*w.leaves[0], 6);
  nine.dice(*w.leaves[0], 9);
  EXPECT_EQ(split.diceBufferBytes, six.bytesAllocated());
  EXPECT_EQ(whole.diceBufferBytes, nine.bytesAllocated());
  EXPECT_GT(double(whole.diceBufferBytes), 40.0 * double(split.diceBufferBytes));  // 4^3 less, less a little for the border tables
}

TEST(SubLeafRuns, TheResidentLevelStaysWhereEveryRayKeepsALevel) {
  EXPECT_EQ(SortedEngine::residentLevelFor(7, 10), 7);
  EXPECT_EQ(SortedEngine::residentLevelFor(3, 10), TraceSettings::kMinResidentLod);
  EXPECT_EQ(SortedEngine::residentLevelFor(6, 12), 6);
  EXPECT_EQ(SortedEngine::residentLevelFor(7, 4), 4);   // never above --max-lod
  EXPECT_EQ(SortedEngine::residentLevelFor(12, 10), 10);
}

}  // namespace
}  // namespace rayes
