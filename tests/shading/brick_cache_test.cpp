// The brick cache (shading/brick_cache.h): a brick is read from its source on the first
// acquire and served from memory after; under a budget smaller than the bricks it evicts and
// re-reads, never holds more slots than the budget allows, never evicts a pinned brick, and
// never more than once when the budget holds every brick; whatever it holds, every acquire
// returns the brick's own voxels, also from many threads at once. A slot's apron holds what was
// filled into it while the slot keeps its brick, and is empty again when the slot is reused.
#include <gtest/gtest.h>
#include <atomic>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include "shading/brick_cache.h"

namespace rayes {
namespace {

// Brick i's voxel v is i·1000 + v; counts its reads.
class CountingSource final : public BrickSource {
 public:
  void read(uint32_t stored, float* voxels) const override {
    reads.fetch_add(1);
    for (uint32_t v = 0; v < BrickCache::kBrickVoxels; ++v) voxels[v] = float(stored) * 1000 + float(v);
  }
  uint64_t residentBytes() const override { return 0; }
  mutable std::atomic<uint64_t> reads{0};
};

// The slot's brick (its padded interior, local 0 … 7) is stored brick `stored`.
bool holdsBrick(const float* padded, uint32_t stored) {
  for (int32_t x = 0; x < 8; ++x)
    for (int32_t y = 0; y < 8; ++y)
      for (int32_t z = 0; z < 8; ++z)
        if (padded[BrickCache::paddedIndex(x, y, z)] != float(stored) * 1000 + float((x * 8 + y) * 8 + z)) return false;
  return true;
}

TEST(BrickCache, FirstAcquireReadsLaterOnesHit) {
  CountingSource source;
  BrickCache cache(64 * BrickCache::kSlotBytes, 1, 16);
  BrickCache::Slot* slot = nullptr;
  for (int round = 0; round < 3; ++round)
    for (uint32_t b = 0; b < 16; ++b) {
      EXPECT_TRUE(holdsBrick(cache.acquire(0, b, source, slot), b));
      cache.release(slot);
    }
  EXPECT_EQ(source.reads.load(), 16u);
  const BrickCacheStats s = cache.stats();
  EXPECT_EQ(s.loads, 16u);
  EXPECT_EQ(s.hits, 32u);
  EXPECT_EQ(s.evictions, 0u);
  EXPECT_EQ(s.voxelsRead, 16u * 512);
  EXPECT_EQ(s.bytesRead, 16u * 512 * 4);
}

TEST(BrickCache, ABudgetHoldingEveryBrickNeverEvictsHoweverTheKeysHash) {
  CountingSource source;
  const uint64_t bricks = 1000;  // many shards, uneven by hashing
  BrickCache cache(bricks * BrickCache::kSlotBytes, 2, bricks);
  BrickCache::Slot* slot = nullptr;
  for (int round = 0; round < 2; ++round)
    for (uint32_t b = 0; b < bricks; ++b) {
      cache.acquire(3, b, source, slot);
      cache.release(slot);
    }
  EXPECT_EQ(cache.stats().evictions, 0u);
  EXPECT_EQ(source.reads.load(), bricks);
}

TEST(BrickCache, ASmallBudgetEvictsStaysWithinItAndStillServesTheRightVoxels) {
  CountingSource source;
  const uint64_t slots = 40, bricks = 400;
  BrickCache cache(slots * BrickCache::kSlotBytes, 2, bricks);
  BrickCache::Slot* slot = nullptr;
  for (int round = 0; round < 3; ++round)
    for (uint32_t b = 0; b < bricks; ++b) {
      ASSERT_TRUE(holdsBrick(cache.acquire(1, b, source, slot), b));
      cache.release(slot);
    }
  const BrickCacheStats s = cache.stats();
  EXPECT_LE(s.slotsUsed, slots);
  EXPECT_GT(s.evictions, 0u);
  EXPECT_EQ(s.loads, source.reads.load());
  EXPECT_EQ(s.loads - s.evictions, s.slotsUsed);  // every load beyond a fresh slot evicted one
}

TEST(BrickCache, APinnedBrickIsNeverEvicted) {
  CountingSource source;
  const int threads = 1;
  BrickCache cache(BrickCache::minimumBytes(threads), threads, 100);
  BrickCache::Slot* pinned = nullptr;
  const float* voxels = cache.acquire(0, 7, source, pinned);
  BrickCache::Slot* slot = nullptr;
  for (uint32_t b = 20; b < 100; ++b) {
    cache.acquire(0, b, source, slot);
    cache.release(slot);
  }
  EXPECT_TRUE(holdsBrick(voxels, 7));  // still in place, not overwritten
  cache.release(pinned);
}

TEST(BrickCache, AnApronRegionFilledOnceStaysUntilTheSlotHoldsAnotherBrick) {
  CountingSource source;
  BrickCache cache(BrickCache::minimumBytes(1), 1, 100);
  BrickCache::Slot* slot = nullptr;
  const float* voxels = cache.acquire(0, 5, source, slot);
  EXPECT_EQ(BrickCache::apronFilled(slot), BrickCache::kInterior);
  // The upper-x face (local x = 8, y and z 0 … 7): 64 values in x-major order of its box.
  const uint32_t face = BrickCache::apronRegion(2, 1, 1), corner = BrickCache::apronRegion(0, 0, 0);
  float values[64];
  for (int i = 0; i < 64; ++i) values[i] = float(-1 - i);
  cache.fillApron(slot, face, values);
  EXPECT_EQ(BrickCache::apronFilled(slot), BrickCache::kInterior | 1u << face);
  EXPECT_EQ(voxels[BrickCache::paddedIndex(8, 0, 0)], -1.0f);
  EXPECT_EQ(voxels[BrickCache::paddedIndex(8, 7, 7)], -64.0f);
  const float other[64] = {};
  cache.fillApron(slot, face, other);  // filled already: kept as it was
  EXPECT_EQ(voxels[BrickCache::paddedIndex(8, 3, 5)], float(-1 - (3 * 8 + 5)));
  const float one = 7;
  cache.fillApron(slot, corner, &one);
  EXPECT_EQ(voxels[BrickCache::paddedIndex(-1, -1, -1)], 7.0f);
  EXPECT_TRUE(holdsBrick(voxels, 5));  // the apron is beside the brick, not over it
  cache.release(slot);
  // Served again from the cache: the apron is still there.
  cache.acquire(0, 5, source, slot);
  EXPECT_EQ(BrickCache::apronFilled(slot), BrickCache::kInterior | 1u << face | 1u << corner);
  cache.release(slot);
  // Every slot reused for other bricks: brick 5 comes back with an empty apron.
  for (uint32_t b = 20; b < 100; ++b) {
    cache.acquire(0, b, source, slot);
    EXPECT_EQ(BrickCache::apronFilled(slot), BrickCache::kInterior);
    cache.release(slot);
  }
  EXPECT_TRUE(holdsBrick(cache.acquire(0, 5, source, slot), 5));
  EXPECT_EQ(BrickCache::apronFilled(slot), BrickCache::kInterior);
  cache.release(slot);
}

TEST(BrickCache, ManyThreadsAtOnceGetTheirOwnBricksVoxels) {
  CountingSource source;
  const int threads = 8;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  BrickCache cache(BrickCache::minimumBytes(threads) * 4, threads, 256);
  std::atomic<int> wrong{0};
  tbb::parallel_for(0, 20000, [&](int i) {
    const uint32_t a = uint32_t(i * 7919) % 256, b = uint32_t(i * 104729 + 13) % 256;
    BrickCache::Slot *sa = nullptr, *sb = nullptr;
    const float* va = cache.acquire(2, a, source, sa);
    const float* vb = cache.acquire(2, b, source, sb);  // two pins per thread, as a GridReader holds
    if (!holdsBrick(va, a) || !holdsBrick(vb, b)) wrong.fetch_add(1);
    cache.release(sb);
    cache.release(sa);
  });
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_LE(cache.stats().slotsUsed, cache.stats().slots);
}

}  // namespace
}  // namespace rayes
