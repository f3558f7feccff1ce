// Thin border regions (BottomQuery::thinBorders) on a curved patch: a ray passing within the
// radius of a level-k border chord, outside the patch, hits that chord's region. The traversal skips a border's whole segment walk when the ray misses
// the bounds of its level-k vertices (DiceBuffer's thinBounds_, built at each dicing): these
// rays are aimed beside every border at every level of dicings of different patches at different
// levels, so bounds that did not hold every segment box, or that were left from an earlier
// dicing, lose hits here.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include "dicing/dice_buffer.h"
#include "geometry/bezier_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Grid (i, j) of vertex s along border e at level k of a level-m grid, and one level-k row inward.
void borderVertex(int e, int k, int m, int s, int inward, int& i, int& j) {
  const int stride = 1 << (m - k), last = 1 << m;
  const int along = s * stride, in = inward * stride;
  switch (e) {
    case 0: i = along; j = in; break;
    case 1: i = last - in; j = along; break;
    case 2: i = along; j = last - in; break;
    default: i = in; j = along; break;
  }
}

Vec3 unit(Vec3 v) { return v * (1.0f / std::sqrt(dot(v, v))); }

TEST(ThinRegions, RaysBesideAChordHitItsRegionAtEveryLevelAfterReDicing) {
  const auto teapot = test::loadTeapot();
  DiceBuffer grid(BottomQuery::kMaxThinLevel);
  int checked = 0;
  for (const auto& [index, m] : {std::pair{0, 6}, std::pair{8, 3}, std::pair{0, 5}, std::pair{20, 4}}) {
    const BezierPatch patch(teapot[size_t(index)]);  // body, handle, body, lid: curved borders
    ASSERT_TRUE(patch.needsBorderClosure());
    const float size = length(patch.bounds().extent());
    const double radius = 1e-3 * size;
    grid.dice(patch, m);
    for (int k = 0; k <= m; ++k)
      for (int e = 0; e < 4; ++e)
        for (int seg = 0; seg < (1 << k); seg += std::max(1, (1 << k) / 4)) {
          int i, j;
          borderVertex(e, k, m, seg, 0, i, j);
          const Vec3 a = grid.position(i, j);
          borderVertex(e, k, m, seg + 1, 0, i, j);
          const Vec3 b = grid.position(i, j);
          borderVertex(e, k, m, seg, 1, i, j);
          Vec3 in = grid.position(i, j);
          borderVertex(e, k, m, seg + 1, 1, i, j);
          in = (in + grid.position(i, j)) * 0.5f;
          if (!(length(b - a) > 1e-4f * size)) continue;  // a pole: the border is a point there
          const Vec3 mid = (a + b) * 0.5f;
          const Vec3 n = unit(cross(b - a, in - mid));
          Vec3 out = mid - in;
          out = unit(out - n * dot(out, n));  // away from the patch, in its tangent plane
          const Vec3 org = mid + out * float(0.5 * radius) + n * size, dir = n * -1.0f;
          GridHit plain;
          if (grid.intersect(org, dir, 0.0f, kInf, k, plain)) continue;  // it meets the surface itself
          BottomQuery q;
          q.closeBorders = true;
          q.thinBorders = 0xf;
          for (double& r : q.thinRadius) r = radius;
          GridHit h;
          ASSERT_TRUE(grid.intersect(org, dir, 0.0f, kInf, k, h, q))
              << "m " << m << " k " << k << " border " << e << " segment " << seg;
          EXPECT_TRUE(h.border);
          EXPECT_TRUE(grid.occluded(org, dir, 0.0f, kInf, k, q)) << "m " << m << " k " << k << " border " << e;
          ++checked;
        }
  }
  // Of the rays aimed (306, less those at poles), those that meet the surface itself prove nothing: at least half do not.
  EXPECT_GT(checked, 153);
}

}  // namespace
}  // namespace rayes
