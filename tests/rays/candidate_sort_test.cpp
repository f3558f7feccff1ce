// CandidateSort groups slots by leaf in (leaf, slot) order, with one run per leaf.
#include <algorithm>
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
  sort.sort(leafOf);
  ASSERT_EQ(sort.order.size(), n);
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(sort.order[i], ref[i].second) << i;
  ASSERT_EQ(sort.runs.back(), n);
  for (size_t r = 0; r + 1 < sort.runs.size(); ++r) {
    const uint32_t leaf = leafOf[sort.order[sort.runs[r]]];
    for (uint32_t i = sort.runs[r]; i < sort.runs[r + 1]; ++i) {
      ASSERT_EQ(leafOf[sort.order[i]], leaf);
    }
    if (r + 2 < sort.runs.size()) {
      ASSERT_NE(leafOf[sort.order[sort.runs[r + 1]]], leaf);
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
  sort.sort({});
  EXPECT_TRUE(sort.order.empty());
  ASSERT_EQ(sort.runs.size(), 1u);
  sort.order = {0};
  sort.sort({5});
  ASSERT_EQ(sort.order.size(), 1u);
  EXPECT_EQ(sort.runs.size(), 2u);
}

}  // namespace
}  // namespace rayes
