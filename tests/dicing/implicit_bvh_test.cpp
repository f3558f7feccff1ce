// Specification of the implicit quad-tree: exact node count, nesting of boxes, memory.
#include <gtest/gtest.h>
#include "geometry/bezier_patch.h"
#include "dicing/dice_buffer.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

size_t sumOfPowersOf4(int m) {
  size_t s = 0;
  for (int i = 0; i <= m; ++i) s += size_t(1) << (2 * i);
  return s;
}

TEST(ImplicitBvh, NodeCountIsExactlySumOfPowersOf4) {
  const auto patches = test::loadTeapot();
  DiceBuffer buffer(7);
  for (int m = 0; m <= 7; ++m) {
    buffer.dice(BezierPatch(patches[m % patches.size()]), m);
    EXPECT_EQ(buffer.level(), m);
    EXPECT_EQ(buffer.resolution(), (1 << m) + 1);
    EXPECT_EQ(buffer.nodeCount(), sumOfPowersOf4(m));
  }
}

TEST(ImplicitBvh, BoxesNestAndLeavesContainTheirQuad) {
  const auto patches = test::loadTeapot();
  DiceBuffer buffer(6);
  for (int p : {0, 8, 16, 20, 28, 31}) {  // body, handle, spout, lid (with a pole), bottom
    for (int m : {0, 1, 3, 6}) {
      const BezierPatch bp(patches[p]);
      buffer.dice(bp, m);
      for (int i = 0; i < m; ++i)
        for (int y = 0; y < (1 << i); ++y)
          for (int x = 0; x < (1 << i); ++x)
            for (int c = 0; c < 4; ++c)
              ASSERT_TRUE(buffer.node(i, x, y).contains(buffer.node(i + 1, 2 * x + (c & 1), 2 * y + (c >> 1))))
                  << "patch " << p << " m " << m << " level " << i;
      for (int y = 0; y < (1 << m); ++y)
        for (int x = 0; x < (1 << m); ++x) {
          const Box3& b = buffer.node(m, x, y);
          ASSERT_FALSE(b.empty());
          for (int c = 0; c < 4; ++c) ASSERT_TRUE(b.contains(buffer.position(x + (c & 1), y + (c >> 1))));
        }
      // The root is the tightest box of the grid, inside the patch's conservative bounds.
      EXPECT_TRUE(bp.bounds().contains(buffer.node(0, 0, 0)));
    }
  }
}

TEST(ImplicitBvh, MemoryIsAllocatedOnceForTheMaxLevel) {
  for (int maxLevel : {0, 3, 8}) {
    DiceBuffer buffer(maxLevel);
    const size_t verts = size_t((1 << maxLevel) + 1) * ((1 << maxLevel) + 1);
    // Grid, tree, and per segment of the 4 borders (2^(maxLevel+1) - 1 each) what a static
    // dicing computes of it on demand: its curve box, its coarse box, two radii (doubles) and
    // four 2-byte stamps.
    const size_t borderSegments = 4 * ((size_t(2) << maxLevel) - 1);
    const size_t expected = 2 * verts * sizeof(Vec3) + sumOfPowersOf4(maxLevel) * sizeof(Box3) +
                            borderSegments * (2 * sizeof(Box3) + 2 * sizeof(double) + 8);
    EXPECT_EQ(buffer.bytesAllocated(), expected);
    const auto patches = test::loadTeapot();
    for (int m = maxLevel; m >= 0; m -= 2) {
      buffer.dice(BezierPatch(patches[0]), m);
      EXPECT_EQ(buffer.bytesAllocated(), expected);
    }
  }
}

TEST(ImplicitBvh, RejectsLevelsOutsideTheAllocation) {
  EXPECT_THROW(DiceBuffer(-1), std::invalid_argument);
  EXPECT_THROW(DiceBuffer(13), std::invalid_argument);
  DiceBuffer buffer(2);
  EXPECT_THROW(buffer.dice(BezierPatch(test::loadTeapot()[0]), 3), std::invalid_argument);
}

}  // namespace
}  // namespace rayes
