// The scene's leaves (geometry/leaf_source.h): a LeafList numbers the leaves of its parts one
// after another in the order they were added, whatever mix of stored patches and generated
// parts; every leaf's box and facts are what its patch says of itself, for a generated forest
// too (whose patches are made again on every call, the same each time).
#include <gtest/gtest.h>
#include <cstring>
#include "geometry/bilinear_patch.h"
#include "geometry/forest_leaves.h"
#include "geometry/leaf_source.h"

namespace rayes {
namespace {

PatchPtr quadAt(float x) {
  return std::make_shared<BilinearPatch>(Vec3{x, 0, 0}, Vec3{x + 1, 0, 0}, Vec3{x, 1, 0}, Vec3{x + 1, 1, 0});
}

std::shared_ptr<const Forest> smallForest() {
  ForestParams p;
  p.trees = 2;
  p.seed = 5;
  p.detail = 2;
  p.terrainTiles = 3;
  p.leavesPerTwig = 3;
  return std::make_shared<const Forest>(p);
}

void expectSameFacts(const LeafFacts& a, const LeafFacts& b, size_t leaf) {
  EXPECT_EQ(a.sizeBound, b.sizeBound) << leaf;
  EXPECT_EQ(a.dicingError, b.dicingError) << leaf;
  EXPECT_EQ(a.timeSamples, b.timeSamples) << leaf;
  EXPECT_STREQ(a.kind, b.kind) << leaf;
  EXPECT_EQ(a.displaced, b.displaced) << leaf;
  EXPECT_EQ(a.subdivision, b.subdivision) << leaf;
  EXPECT_EQ(a.borderClosure, b.borderClosure) << leaf;
}

bool sameBox(const Box3& a, const Box3& b) { return std::memcmp(&a, &b, sizeof(Box3)) == 0; }

TEST(LeafList, LeafIdsRunThroughThePartsInTheOrderAdded) {
  const auto forest = smallForest();
  LeafList list;
  list.add(quadAt(0));
  list.add(quadAt(2));
  list.add(std::make_shared<const ForestLeaves>(forest));
  list.add(quadAt(4));
  ASSERT_EQ(list.size(), 3 + forest->size());
  EXPECT_EQ(list.patch(1)->evaluate(0, 0).p.x, 2.0f);
  EXPECT_EQ(list.patch(2 + forest->size())->evaluate(0, 0).p.x, 4.0f);
  for (size_t i = 0; i < forest->size(); ++i) ASSERT_TRUE(sameBox(list.bounds(2 + i), forest->bounds(i))) << i;
}

TEST(LeafList, EmptyPartsTakeNoIds) {
  LeafList list;
  list.add(std::make_shared<const StoredLeaves>());
  list.add(quadAt(7));
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list.patch(0)->evaluate(0, 0).p.x, 7.0f);
  EXPECT_TRUE(sameBox(list.bounds(0), quadAt(7)->bounds()));
}

TEST(ForestLeaves, FactsAndBoundsAreWhatEveryMadePatchSays) {
  const ForestLeaves leaves(smallForest());
  bool parts[3] = {};
  for (size_t i = 0; i < leaves.size(); ++i) {
    const PatchPtr p = leaves.patch(i);
    expectSameFacts(leaves.facts(i), LeafFacts::of(*p), i);
    ASSERT_TRUE(sameBox(leaves.bounds(i), p->bounds())) << i;
    ASSERT_TRUE(sameBox(leaves.patch(i)->bounds(), p->bounds())) << "made twice, leaf " << i;
    parts[size_t(leaves.forest().leaf(i).part)] = true;
  }
  EXPECT_TRUE(parts[0] && parts[1] && parts[2]);  // terrain, bark and foliage were all checked
  EXPECT_GT(leaves.descriptionBytes(), 0u);
}

TEST(StoredLeaves, FactsAreThePatchsOwn) {
  const StoredLeaves leaves({quadAt(0), quadAt(1)});
  expectSameFacts(leaves.facts(1), LeafFacts::of(*quadAt(1)), 1);
  EXPECT_FALSE(leaves.facts(0).borderClosure);  // bilinear borders are straight
}

}  // namespace
}  // namespace rayes
