// Sub-leaves (geometry/sub_patch.h, issue 33 item 2): a leaf split into 4^depth sub-leaves is
// the same surface, diced the same. What could go wrong, and is checked here:
// - a sub-leaf's grid is not the parent's finer grid (a vertex computed from sub-rectangle
//   arithmetic rounds differently on the two sides of a shared edge, or differently from the
//   parent's own border vertex that its neighbouring leaves match): compared bit for bit;
// - a sub-leaf's box misses a vertex it dices (the top level would skip a hit);
// - the crack-closing pieces of a sub-leaf's border on the parent's border are not the parent's.
// Rays aimed at shared edges and corners of sub-leaves are in watertight_test.cpp.
#include <gtest/gtest.h>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include "dicing/dice_buffer.h"
#include "geometry/bezier_patch.h"
#include "geometry/sub_patch.h"
#include "support/displaced_test_shapes.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::sameBits;

std::vector<test::Shape> curvedDisplacedShapes() {
  std::vector<test::Shape> out;
  for (const test::Shape& shape : test::testShapes()) {
    out.push_back(shape);
    for (const test::Displaced& d : test::testDisplacements(shape.patch->bounds().longestSide()))
      out.push_back({d.name, std::make_shared<DisplacedPatch>(shape.patch, d.d)});
  }
  return out;
}

TEST(SubLeaf, GridIsTheParentsFinerGridBitForBit) {
  for (const test::Shape& shape : curvedDisplacedShapes())
    for (int depth = 1; depth <= 3; ++depth)
      for (int m = 0; m <= 4; ++m) {
        DiceBuffer parent(m + depth), sub(m);
        parent.dice(*shape.patch, m + depth);
        const int n = 1 << m;
        for (uint32_t y = 0; y < (1u << depth); ++y)
          for (uint32_t x = 0; x < (1u << depth); ++x) {
            const SubPatch leaf(shape.patch, depth, x, y);
            sub.dice(leaf, m);
            for (int j = 0; j <= n; ++j)
              for (int i = 0; i <= n; ++i) {
                const int pi = int(x) * n + i, pj = int(y) * n + j;
                ASSERT_TRUE(sameBits(sub.position(i, j), parent.position(pi, pj)))
                    << shape.name << " depth " << depth << " m " << m << " sub (" << x << ", " << y << ") vertex (" << i
                    << ", " << j << ")";
                ASSERT_TRUE(sameBits(sub.normal(i, j), parent.normal(pi, pj))) << shape.name;
              }
          }
      }
}

TEST(SubLeaf, ParametersMapExactlyOntoTheParentsGrid) {
  const auto parent = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  const SubPatch leaf(parent, 3, 5, 2);
  EXPECT_EQ(leaf.parentU(0.0f), 5.0f / 8);
  EXPECT_EQ(leaf.parentU(1.0f), 6.0f / 8);
  EXPECT_EQ(leaf.parentV(0.25f), (2.0f + 0.25f) / 8);
  // The finest level a sub-leaf of depth 8 can be diced at keeps every index exact.
  const SubPatch deep(parent, 8, 255, 255);
  EXPECT_EQ(deep.parentU(std::ldexp(float((1 << 16) - 1), -16)), std::ldexp(float((1 << 24) - 1), -24));
}

TEST(SubLeaf, BoundsHoldEveryDicedVertex) {
  for (const test::Shape& shape : curvedDisplacedShapes()) {
    DiceBuffer sub(6);
    for (uint32_t y = 0; y < 4; ++y)
      for (uint32_t x = 0; x < 4; ++x) {
        const SubPatch leaf(shape.patch, 2, x, y);
        const Box3 b = leaf.bounds();
        ASSERT_TRUE(shape.patch->bounds().contains(b.lo) && shape.patch->bounds().contains(b.hi))
            << shape.name << ": a sub-leaf's box outside its parent's";
        for (int m = 0; m <= 6; m += 3) {
          sub.dice(leaf, m);
          for (int j = 0; j < sub.resolution(); ++j)
            for (int i = 0; i < sub.resolution(); ++i)
              ASSERT_TRUE(b.contains(sub.position(i, j))) << shape.name << " sub (" << x << ", " << y << ") m " << m;
        }
      }
  }
}

TEST(SubLeaf, SizesScaleWithTheSplit) {
  const auto parent = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  const SubPatch leaf(parent, 3, 1, 1);
  EXPECT_EQ(leaf.sizeBound(), parent->sizeBound() / 8);
  EXPECT_EQ(leaf.dicingErrorCoefficient(), parent->dicingErrorCoefficient() / 64);
  // The level-of-detail floor of a sub-leaf is not its parent's minus the depth (the floor is
  // relative to the size), which is why an engine must take a sub-leaf's levels from its parent.
  EXPECT_EQ(leaf.needsBorderClosure(), parent->needsBorderClosure());
  EXPECT_STREQ(leaf.kind(), parent->kind());
}

TEST(SubLeaf, BorderPiecesOnTheParentsBorderAreTheParents) {
  const auto parent = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  const int depth = 2, k = 2, split = 3;
  Box3 mine[1 << split], theirs[1 << split];
  for (int e = 0; e < 4; ++e)
    for (uint32_t y = 0; y < 4; ++y)
      for (uint32_t x = 0; x < 4; ++x) {
        const SubPatch leaf(parent, depth, x, y);
        if (!leaf.onParentBorder(e)) continue;
        const uint32_t offset = (e == 0 || e == 2) ? x : y;
        for (uint32_t j = 0; j < (1u << k); ++j) {
          leaf.borderPieceBoundsAt(0, e, k, j, split, mine);
          parent->borderPieceBoundsAt(0, e, k + depth, (offset << k) + j, split, theirs);
          for (int i = 0; i < (1 << split); ++i)
            ASSERT_TRUE(sameBits(mine[i].lo, theirs[i].lo) && sameBits(mine[i].hi, theirs[i].hi)) << "border " << e;
        }
      }
  // Each border lies on the parent's border exactly where its sub-rectangle touches it.
  const SubPatch corner(parent, depth, 3, 0), inner(parent, depth, 1, 2);
  EXPECT_TRUE(corner.onParentBorder(0) && corner.onParentBorder(1));
  EXPECT_FALSE(corner.onParentBorder(2) || corner.onParentBorder(3));
  for (int e = 0; e < 4; ++e) EXPECT_FALSE(inner.onParentBorder(e));
}

TEST(SubLeaf, BorderPiecesHoldTheSubLeafsBorderVertices) {
  for (const test::Shape& shape : curvedDisplacedShapes()) {
    const int depth = 2, m = 5, k = 2, split = 3;
    DiceBuffer sub(m);
    Box3 pieces[1 << split];
    for (uint32_t y = 0; y < 4; ++y)
      for (uint32_t x = 0; x < 4; ++x) {
        const SubPatch leaf(shape.patch, depth, x, y);
        sub.dice(leaf, m);
        const int n = 1 << m, perPiece = n >> (k + split);
        for (int e = 0; e < 4; ++e)
          for (uint32_t j = 0; j < (1u << k); ++j) {
            leaf.borderPieceBoundsAt(0, e, k, j, split, pieces);
            for (int i = 0; i < (1 << split); ++i)
              for (int t = 0; t <= perPiece; ++t) {
                // Borders as DiceBuffer numbers them: 0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0.
                const int along = (int(j) << split | i) * perPiece + t;
                const int vi = e == 0 || e == 2 ? along : (e == 1 ? n : 0), vj = e == 1 || e == 3 ? along : (e == 2 ? n : 0);
                ASSERT_TRUE(pieces[i].contains(sub.position(vi, vj)))
                    << shape.name << " sub (" << x << ", " << y << ") border " << e;
              }
          }
      }
  }
}

TEST(SubLeaf, DepthIsTheExcessOverTheResidentMaximum) {
  EXPECT_EQ(subLeafDepth(10, 6), 4);
  EXPECT_EQ(subLeafDepth(6, 6), 0);
  EXPECT_EQ(subLeafDepth(3, 6), 0);
  EXPECT_EQ(subLeafDepth(10, -1), 10);
}

TEST(SubLeaf, RefusesWhatItCannotRepresent) {
  const auto parent = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  EXPECT_THROW(SubPatch(nullptr, 1, 0, 0), std::invalid_argument);
  EXPECT_THROW(SubPatch(parent, -1, 0, 0), std::invalid_argument);
  EXPECT_THROW(SubPatch(parent, SubPatch::kMaxDepth + 1, 0, 0), std::invalid_argument);
  EXPECT_THROW(SubPatch(parent, 2, 4, 0), std::invalid_argument);
  EXPECT_THROW(SubPatch(parent, 2, 0, 4), std::invalid_argument);
}

// The memory a resident maximum saves: a dice buffer's bytes by its maximum level (printed:
// the figures bench/history/2026-11.md "Sub-leaves" quotes), about 4x per level.
TEST(SubLeaf, ABufferCostsAboutFourTimesMorePerLevel) {
  const auto parent = std::make_shared<BezierPatch>(test::loadTeapot()[0]);
  double previous = 0;
  for (int m = 4; m <= 10; ++m) {
    DiceBuffer buffer(m);
    buffer.dice(*parent, m);
    const double bytes = double(buffer.bytesAllocated());
    std::printf("[ dice buffer ] level %d: %.0f bytes (%.2f MiB)\n", m, bytes, bytes / 1048576.0);
    if (m > 6) {  // the grid and tree grow 4x, the border tables 2x
      EXPECT_GT(bytes, 3.7 * previous) << m;
    }
    previous = bytes;
  }
}

}  // namespace
}  // namespace rayes
