// SortScratch (core/sort_scratch.h): the memory the sorts of one RayBatch take in turn. Each
// take() hands out the same storage as typed objects, growing it only for a larger request,
// so two stages that never overlap share one allocation of the larger need.
#include <cstdint>
#include <gtest/gtest.h>
#include "core/ray_batch.h"
#include "core/sort_scratch.h"

namespace rayes {
namespace {

struct Pair {
  uint32_t key, value;
};

TEST(SortScratch, StagesTakeTheSameStorageAndItGrowsOnlyForALargerNeed) {
  SortScratch s;
  EXPECT_EQ(s.bytes(), 0u);
  EXPECT_TRUE(s.take<uint32_t>(0).empty());  // nothing asked: nothing allocated
  EXPECT_EQ(s.bytes(), 0u);
  const std::span<uint32_t> words = s.take<uint32_t>(100);
  ASSERT_EQ(words.size(), 100u);
  EXPECT_EQ(s.bytes(), 400u);
  for (uint32_t i = 0; i < 100; ++i) words[i] = i;  // the whole span is writable
  // A later stage's smaller need of another type: the same memory, no new allocation.
  const std::span<Pair> pairs = s.take<Pair>(50);
  ASSERT_EQ(pairs.size(), 50u);
  EXPECT_EQ(static_cast<void*>(pairs.data()), static_cast<void*>(words.data()));
  EXPECT_EQ(s.bytes(), 400u);
  pairs[49] = {7, 8};
  EXPECT_EQ(pairs[49].value, 8u);
  // A larger need grows it to exactly that need.
  EXPECT_EQ(s.take<Pair>(60).size(), 60u);
  EXPECT_EQ(s.bytes(), 480u);
  EXPECT_EQ(s.take<uint32_t>(1).size(), 1u);
  EXPECT_EQ(s.bytes(), 480u);  // never shrinks
}

// A batch copied (tests copy batches to trace them twice) starts without scratch: nothing in it
// outlives the stage that took it, so there is nothing to copy.
TEST(SortScratch, ACopiedBatchStartsWithoutScratch) {
  RayBatch a;
  a.sortScratch.take<uint32_t>(64);
  const RayBatch b = a;
  EXPECT_EQ(b.sortScratch.bytes(), 0u);
  EXPECT_EQ(a.sortScratch.bytes(), 256u);
  RayBatch c;
  c = a;
  EXPECT_EQ(c.sortScratch.bytes(), 0u);
}

}  // namespace
}  // namespace rayes
