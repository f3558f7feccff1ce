// BorderBoundCache (dicing/border_bound_cache.h): the border boxes and radii kept across the
// dicings of a render are the values a dicing would compute itself, the table never grows, and
// concurrent use never hands out another key's value.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <atomic>
#include <cstring>
#include <limits>
#include <memory>
#include "dicing/border_bound_cache.h"
#include "dicing/dice_buffer.h"
#include "geometry/bezier_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// A displaced teapot patch: curved borders, and bounds that cost boundsOver calls.
std::shared_ptr<DisplacedPatch> displacedTeapot() {
  NoiseParams noise;
  noise.amplitude = 0.05f;
  noise.frequency = 3.0f;
  noise.octaves = 4;
  return std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(test::loadTeapot()[0]),
                                          std::make_shared<NoiseDisplacement>(noise));
}

bool sameHit(const GridHit& a, const GridHit& b) {
  return a.t == b.t && a.u == b.u && a.v == b.v && a.quad == b.quad && a.border == b.border && a.ng == b.ng &&
         a.ns == b.ns;
}

// Rays at border points from outside along the normal, each at its own level: they walk the
// segment boxes of levels 0..k and need both radii of the segment they reach.
template <class F>
void forBorderRays(const Patch& patch, int m, F&& f) {
  test::Random rnd(5);
  for (int r = 0; r < 600; ++r) {
    const test::BorderRay ray = test::randomBorderRay(patch, rnd, 0.05f, 0.95f, m);
    f(ray.org, ray.dir, ray.level);
  }
}

// A dicing that reads what another dicing (at another level) left in the table gets exactly
// the hits of a dicing that computes everything itself.
TEST(BorderBoundCache, CachedBoundsGiveTheHitsOfRecomputedOnes) {
  constexpr int m = 5;
  const auto patch = displacedTeapot();
  ASSERT_TRUE(patch->needsBorderClosure());
  BorderBoundCache cache(1 << 14);
  DiceBuffer alone(m), filler(m), reader(m);
  alone.dice(*patch, m);
  filler.dice(*patch, m, {&cache, 3});
  reader.dice(*patch, m - 1, {&cache, 3});
  BottomQuery q;
  q.closeBorders = true;
  int borderHits = 0;
  forBorderRays(*patch, m - 1, [&](Vec3 org, Vec3 dir, int k) {
    GridHit h;
    filler.intersect(org, dir, 0.0f, kInf, k, h, q);
  });
  EXPECT_GT(cache.bytes(), 0u);
  forBorderRays(*patch, m - 1, [&](Vec3 org, Vec3 dir, int k) {
    GridHit expected, cached;
    const bool e = alone.intersect(org, dir, 0.0f, kInf, k, expected, q);
    ASSERT_EQ(reader.intersect(org, dir, 0.0f, kInf, k, cached, q), e);
    if (e) {
      ASSERT_TRUE(sameHit(expected, cached)) << expected.t << " " << cached.t;
    }
    borderHits += e && expected.border;
    ASSERT_EQ(reader.occluded(org, dir, 0.0f, kInf, k, q), alone.occluded(org, dir, 0.0f, kInf, k, q));
  });
  EXPECT_GT(borderHits, 0);  // the regions, and so the radii, were exercised
  for (int e = 0; e < 4; ++e)
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < (1 << i); ++j) {
        const Box3 a = alone.borderNode(e, i, j), b = reader.borderNode(e, i, j);
        ASSERT_TRUE(a.lo == b.lo && a.hi == b.hi) << e << " " << i << " " << j;
      }
}

// The equality above would hold trivially if dicings never read the table: a value planted
// under the leaf's key is what the dicing uses; under another leaf's key it is not.
TEST(BorderBoundCache, DicingsReadTheirOwnLeafsEntries) {
  const auto patch = displacedTeapot();
  BorderBoundCache cache(64);
  Box3 planted;
  planted.lo = {-7, -7, -7};
  planted.hi = {7, 7, 7};
  cache.insert({9, BorderBoundCache::Kind::CurveBox, 2, 0, 0}, planted);
  DiceBuffer own(3), other(3);
  own.dice(*patch, 3, {&cache, 9});
  other.dice(*patch, 3, {&cache, 10});
  EXPECT_TRUE(own.borderNode(2, 0, 0).contains(planted.hi));
  EXPECT_FALSE(other.borderNode(2, 0, 0).contains(planted.hi));
}

double valueOf(uint32_t leaf, uint32_t segment) { return double(leaf) * 1e3 + segment + 0.25; }

// Far more keys than entries: the bytes stay capacity x entryBytes, the newest key of a slot is
// found, and whatever is found is its own key's value (eviction overwrites, never mixes).
TEST(BorderBoundCache, EvictionKeepsItBounded) {
  BorderBoundCache cache(100);
  EXPECT_EQ(cache.capacity(), 128u);
  EXPECT_EQ(cache.bytes(), 0u);  // nothing allocated before the first insert
  for (uint32_t leaf = 0; leaf < 200; ++leaf)
    for (uint32_t j = 0; j < 50; ++j) {
      const BorderBoundCache::Key key{leaf, BorderBoundCache::Kind::FineRadius, 1, 6, j};
      cache.insert(key, valueOf(leaf, j));
      double r = 0;
      ASSERT_TRUE(cache.find(key, r));
      ASSERT_EQ(r, valueOf(leaf, j));
      ASSERT_EQ(cache.bytes(), 128 * BorderBoundCache::entryBytes());
    }
  int found = 0;
  for (uint32_t leaf = 0; leaf < 200; ++leaf)
    for (uint32_t j = 0; j < 50; ++j) {
      double r;
      if (!cache.find({leaf, BorderBoundCache::Kind::FineRadius, 1, 6, j}, r)) continue;
      ASSERT_EQ(r, valueOf(leaf, j));
      ++found;
    }
  EXPECT_LE(found, 128);
  EXPECT_GT(found, 0);
  // The kinds, borders and levels are distinct keys.
  double r;
  EXPECT_FALSE(cache.find({199, BorderBoundCache::Kind::CoarseRadius, 1, 6, 49}, r));
  EXPECT_FALSE(cache.find({199, BorderBoundCache::Kind::FineRadius, 0, 6, 49}, r));
  EXPECT_FALSE(cache.find({199, BorderBoundCache::Kind::FineRadius, 1, 5, 49}, r));
}

// Two or more threads inserting and reading colliding keys of a small table: every value found
// is its key's, boxes and radii alike (the seqlock turns a torn read into a miss).
TEST(BorderBoundCache, ThreadSafeUnderParallelFor) {
  BorderBoundCache cache(64);
  std::atomic<int> wrong{0}, hits{0};
  tbb::parallel_for(0, 200000, [&](int i) {
    const uint32_t leaf = uint32_t(i % 997), j = uint32_t(i % 13);
    const BorderBoundCache::Key rk{leaf, BorderBoundCache::Kind::CoarseRadius, 3, 2, j};
    const BorderBoundCache::Key bk{leaf, BorderBoundCache::Kind::CurveBox, 3, 2, j};
    const float s = float(valueOf(leaf, j));
    Box3 box;
    box.lo = {s, s + 1, s + 2};
    box.hi = {s + 3, s + 4, s + 5};
    if (i % 3 == 0) {
      cache.insert(rk, valueOf(leaf, j));
      cache.insert(bk, box);
    }
    double r;
    if (cache.find(rk, r)) {
      hits.fetch_add(1, std::memory_order_relaxed);
      if (r != valueOf(leaf, j)) wrong.fetch_add(1);
    }
    Box3 b;
    if (cache.find(bk, b) && !(b.lo == box.lo && b.hi == box.hi)) wrong.fetch_add(1);
  });
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_GT(hits.load(), 0);
  EXPECT_EQ(cache.bytes(), 64 * BorderBoundCache::entryBytes());
}

}  // namespace
}  // namespace rayes
