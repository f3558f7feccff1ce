// shadeRanks: a leaf's rank is its place in (material, leaf) order, the shading sort's 32-bit key.
#include <algorithm>
#include <gtest/gtest.h>
#include "shading/shading_scene.h"

namespace rayes {
namespace {

TEST(ShadeRanks, AreThePlacesInMaterialThenLeafOrder) {
  const std::vector<uint32_t> material = {2, 0, 2, 1, 0, 7, 2};  // unused materials in between
  const std::vector<uint32_t> rank = shadeRanks(material);
  std::vector<std::pair<uint32_t, uint32_t>> order;
  for (uint32_t l = 0; l < material.size(); ++l) order.push_back({material[l], l});
  std::sort(order.begin(), order.end());
  ASSERT_EQ(rank.size(), material.size());
  for (uint32_t r = 0; r < order.size(); ++r) EXPECT_EQ(rank[order[r].second], r) << "leaf " << order[r].second;
}

TEST(ShadeRanks, NoLeavesAndOneMaterial) {
  EXPECT_TRUE(shadeRanks({}).empty());
  EXPECT_EQ(shadeRanks({0, 0, 0}), (std::vector<uint32_t>{0, 1, 2}));
}

}  // namespace
}  // namespace rayes
