// DisplacedPatch diced through a DiceBuffer (docs/design.md, invariant 1 with displacement): every
// vertex of a level-8 grid of every test shape and displacement lies inside bounds(), with a
// finite normal. The patch itself is specified in tests/geometry/displace_patch_test.cpp.
#include <gtest/gtest.h>
#include "dicing/dice_buffer.h"
#include "geometry/displaced_patch.h"
#include "support/displaced_test_shapes.h"

namespace rayes {
namespace {

using test::Displaced;
using test::Shape;
using test::testDisplacements;
using test::testShapes;

TEST(DisplacedPatch, DicedGridInsideBoundsAndDiceBufferWorks) {
  DiceBuffer buffer(8);
  for (const Shape& shape : testShapes()) {
    const float size = shape.patch->bounds().longestSide();
    for (const Displaced& disp : testDisplacements(size)) {
      const DisplacedPatch patch(shape.patch, disp.d);
      buffer.dice(patch, 8);
      const Box3 b = patch.bounds();
      for (int j = 0; j < buffer.resolution(); ++j)
        for (int i = 0; i < buffer.resolution(); ++i) {
          ASSERT_TRUE(b.contains(buffer.position(i, j))) << shape.name << " / " << disp.name;
          ASSERT_TRUE(isFinite(buffer.normal(i, j)));
        }
      EXPECT_TRUE(b.contains(buffer.node(0, 0, 0)));
    }
  }
}

}  // namespace
}  // namespace rayes
