// GridCache (rays/grid_cache.h): a leaf held at level m serves any level <= m without a new
// dicing; a finer request re-dices; the byte budget is never exceeded; entries handed out in the
// current iteration are never evicted (the parallel step is still using them), least recently used
// ones are. A leaf's sub-leaves are grids of their own, under their own keys, evicted like any
// other; an entry made to dice into and not diced goes back whole.
#include <gtest/gtest.h>
#include "geometry/bilinear_patch.h"
#include "rays/grid_cache.h"

namespace rayes {
namespace {

size_t gridBytes(int level) { return DiceBuffer(level).bytesAllocated(); }

// What the SortedEngine does with an entry: dices into it when asked to.
GridCache::Entry* acquireAndDice(GridCache& cache, GridKey key, int level) {
  GridCache::Entry* e = cache.acquire(key, level);
  if (e && e->toDice) {
    e->patch = std::make_shared<BilinearPatch>(Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0.5f});
    e->gridToDice().dice(*e->patch, level);
  }
  return e;
}

// acquire() charges a new grid's bytes before the grid exists (it is made by the parallel step
// that dices it): what it charges is what the grid then holds.
TEST(GridCache, ChargesANewGridWhatItHoldsAndLeavesItToTheDicer) {
  for (int level = 0; level <= 8; ++level) EXPECT_EQ(DiceBuffer::bytesFor(level), gridBytes(level)) << level;
  GridCache cache(1 << 20);
  GridCache::Entry* e = cache.acquire(3, 2);
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(e->toDice);
  EXPECT_EQ(e->grid, nullptr);
  EXPECT_EQ(cache.bytes(), gridBytes(2));
  EXPECT_EQ(e->gridToDice().maxLevel(), 2);
  EXPECT_EQ(&e->gridToDice(), e->grid.get()) << "made once";
}

TEST(GridCache, HoldsALeafAndServesItsLevelAndCoarserOnes) {
  GridCache cache(1 << 20);
  GridCache::Entry* e = acquireAndDice(cache, 7, 3);
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(e->toDice);
  EXPECT_EQ(e->grid->maxLevel(), 3);
  EXPECT_EQ(cache.bytes(), gridBytes(3));
  cache.nextIteration();
  for (int level : {3, 1, 0}) {
    GridCache::Entry* again = acquireAndDice(cache, 7, level);
    ASSERT_EQ(again, e);
    EXPECT_FALSE(again->toDice) << level;
    cache.nextIteration();
  }
  EXPECT_EQ(cache.hits(), 3u);
}

TEST(GridCache, AFinerRequestIsDicedAgainAtTheFinerLevel) {
  GridCache cache(1 << 20);
  acquireAndDice(cache, 7, 1);
  cache.nextIteration();
  GridCache::Entry* e = cache.acquire(7, 4);
  ASSERT_NE(e, nullptr);
  EXPECT_TRUE(e->toDice);
  EXPECT_EQ(e->level, 4);
  EXPECT_EQ(e->gridToDice().maxLevel(), 4);
  EXPECT_EQ(cache.entries(), 1u);
  EXPECT_EQ(cache.bytes(), gridBytes(4));  // the coarse grid's bytes are given back
  EXPECT_EQ(cache.hits(), 0u);
}

TEST(GridCache, NeverEvictsAnEntryOfTheCurrentIteration) {
  GridCache cache(gridBytes(2) + gridBytes(2) / 2);  // room for one level-2 grid
  ASSERT_NE(cache.acquire(1, 2), nullptr);
  EXPECT_EQ(cache.acquire(2, 2), nullptr);  // leaf 1 is in use: leaf 2 is diced uncached
  EXPECT_EQ(cache.entries(), 1u);
  cache.nextIteration();
  GridCache::Entry* e = cache.acquire(2, 2);  // now leaf 1 may go
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->key.leaf, 2u);
  EXPECT_EQ(cache.entries(), 1u);
  EXPECT_LE(cache.peakBytes(), gridBytes(2) + gridBytes(2) / 2);
}

TEST(GridCache, EvictsTheLeastRecentlyUsed) {
  GridCache cache(3 * gridBytes(1));
  for (uint32_t leaf : {1u, 2u, 3u}) acquireAndDice(cache, leaf, 1);
  cache.nextIteration();
  acquireAndDice(cache, 1, 1);  // 2 is now the least recently used
  cache.nextIteration();
  acquireAndDice(cache, 4, 1);
  cache.nextIteration();
  EXPECT_FALSE(acquireAndDice(cache, 1, 1)->toDice);
  cache.nextIteration();
  EXPECT_FALSE(acquireAndDice(cache, 3, 1)->toDice);
  cache.nextIteration();
  EXPECT_TRUE(acquireAndDice(cache, 2, 1)->toDice);  // evicted, diced again
  EXPECT_LE(cache.peakBytes(), 3 * gridBytes(1));
}

TEST(GridCache, AGridLargerThanTheBudgetIsNotCached) {
  GridCache cache(gridBytes(3) - 1);
  EXPECT_EQ(cache.acquire(1, 3), nullptr);
  EXPECT_EQ(cache.bytes(), 0u);
  GridCache off(0);
  EXPECT_FALSE(off.enabled());
  EXPECT_EQ(off.acquire(1, 0), nullptr);
}

TEST(GridCache, ALeafWholeAndEachOfItsSubLeavesAreSeparateGrids) {
  GridCache cache(1 << 20);
  const GridKey whole(7), sub(7, 1, 0, 1), sibling(7, 1, 1, 0), deeper(7, 2, 0, 1);
  GridCache::Entry* entries[4];
  int k = 0;
  for (const GridKey& key : {whole, sub, sibling, deeper}) {
    entries[k] = acquireAndDice(cache, key, 2);
    ASSERT_NE(entries[k], nullptr);
    EXPECT_TRUE(entries[k]->toDice) << k;  // none served by another
    EXPECT_EQ(entries[k]->key, key);
    ++k;
  }
  EXPECT_EQ(cache.entries(), 4u);
  EXPECT_EQ(cache.bytes(), 4 * gridBytes(2));
  cache.nextIteration();
  k = 0;
  for (const GridKey& key : {whole, sub, sibling, deeper}) {
    GridCache::Entry* again = acquireAndDice(cache, key, 1);
    EXPECT_EQ(again, entries[k++]);
    EXPECT_FALSE(again->toDice);
  }
  EXPECT_EQ(cache.hits(), 4u);
}

TEST(GridCache, AnEntryMadeAndNotDicedIsDiscardedWhole) {
  GridCache cache(1 << 20);
  GridCache::Entry* kept = acquireAndDice(cache, GridKey(3, 1, 1, 1), 2);
  GridCache::Entry* unused = cache.acquire(GridKey(3, 1, 0, 1), 2);
  ASSERT_NE(unused, nullptr);
  ASSERT_TRUE(unused->toDice);
  cache.discard(unused);
  cache.discard(kept);     // diced: stays
  cache.discard(nullptr);  // not cached: nothing to give back
  EXPECT_EQ(cache.entries(), 1u);
  EXPECT_EQ(cache.bytes(), gridBytes(2));
  EXPECT_EQ(cache.peakBytes(), 2 * gridBytes(2));
  cache.nextIteration();
  EXPECT_TRUE(cache.acquire(GridKey(3, 1, 0, 1), 2)->toDice);  // made again, not a hit
  EXPECT_FALSE(cache.acquire(GridKey(3, 1, 1, 1), 2)->toDice);
  EXPECT_EQ(cache.hits(), 1u);
}

TEST(GridCache, EvictsTheLeastRecentlyUsedSubLeaf) {
  GridCache cache(3 * gridBytes(1));
  for (uint32_t x : {0u, 1u}) acquireAndDice(cache, GridKey(5, 1, x, 0), 1);
  acquireAndDice(cache, GridKey(5), 1);
  cache.nextIteration();
  acquireAndDice(cache, GridKey(5, 1, 0, 0), 1);  // sub-leaf (1, 0) is now the least recently used
  cache.nextIteration();
  EXPECT_TRUE(acquireAndDice(cache, GridKey(9, 1, 1, 1), 1)->toDice);
  cache.nextIteration();
  EXPECT_EQ(cache.entries(), 3u);
  EXPECT_FALSE(acquireAndDice(cache, GridKey(5), 1)->toDice);
  EXPECT_FALSE(acquireAndDice(cache, GridKey(5, 1, 0, 0), 1)->toDice);
  cache.nextIteration();
  EXPECT_TRUE(acquireAndDice(cache, GridKey(5, 1, 1, 0), 1)->toDice);  // evicted, diced again
  EXPECT_LE(cache.peakBytes(), 3 * gridBytes(1));
}

}  // namespace
}  // namespace rayes
