// CandidateSort groups slots by leaf in (leaf, slot) order, with one run per leaf, in the
// caller's `order` and the scratch it lends: the result in one, the other left free (`spare`).
#include <algorithm>
#include <stdexcept>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "rays/candidate_sort.h"

namespace rayes {
namespace {

void expectSortedLikeStdSort(size_t n, uint32_t leaves, bool sparseSlots) {
  std::vector<uint32_t> slots, leafOf(3 * n + 1);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t s = uint32_t(sparseSlots ? 3 * i + 1 : i);
    slots.push_back(s);
    leafOf[s] = uint32_t(sampleUniform(RngKey{uint32_t(i), 0, 0, leaves}, 0) * float(leaves)) % leaves;
  }
  std::vector<std::pair<uint32_t, uint32_t>> ref;
  for (uint32_t s : slots) ref.push_back({leafOf[s], s});
  std::sort(ref.begin(), ref.end());
  CandidateSort sort;
  sort.order = slots;
  std::vector<uint32_t> scratch(n + 3);  // more than needed: the sort uses the first n words
  sort.sort(leafOf, scratch);
  ASSERT_EQ(sort.sorted.size(), n);
  ASSERT_EQ(sort.spare.size(), n);
  // The result and the spare words are the two buffers, one each.
  const bool inOrder = sort.sorted.data() == sort.order.data();
  EXPECT_TRUE(inOrder || sort.sorted.data() == scratch.data());
  EXPECT_EQ(sort.spare.data(), inOrder ? scratch.data() : sort.order.data());
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(sort.sorted[i], ref[i].second) << i;
  ASSERT_EQ(sort.runs.back(), n);
  for (size_t r = 0; r + 1 < sort.runs.size(); ++r) {
    const uint32_t leaf = leafOf[sort.sorted[sort.runs[r]]];
    for (uint32_t i = sort.runs[r]; i < sort.runs[r + 1]; ++i) {
      ASSERT_EQ(leafOf[sort.sorted[i]], leaf);
    }
    if (r + 2 < sort.runs.size()) {
      ASSERT_NE(leafOf[sort.sorted[sort.runs[r + 1]]], leaf);
    }
  }
}

TEST(CandidateSort, EqualsStdSortOfLeafSlotPairs) {
  expectSortedLikeStdSort(1000, 7, false);
  expectSortedLikeStdSort(300000, 100000, true);     // several blocks, two radix passes
  expectSortedLikeStdSort(200000, 1u << 30, false);  // three passes, huge leaf ids
}

TEST(CandidateSort, EmptyAndSingle) {
  CandidateSort sort;
  sort.sort({}, {});
  EXPECT_TRUE(sort.sorted.empty());
  ASSERT_EQ(sort.runs.size(), 1u);
  sort.order = {0};
  uint32_t scratch = 0;
  sort.sort({5}, {&scratch, 1});
  ASSERT_EQ(sort.sorted.size(), 1u);
  EXPECT_EQ(sort.sorted[0], 0u);
  EXPECT_EQ(sort.runs.size(), 2u);
}

// Lent less scratch than it has slots, it refuses rather than write past the caller's memory.
TEST(CandidateSort, RefusesTooLittleScratch) {
  CandidateSort sort;
  sort.order = {0, 1};
  uint32_t scratch = 0;
  EXPECT_THROW(sort.sort({3, 4}, {&scratch, 1}), std::logic_error);
}

}  // namespace
}  // namespace rayes
