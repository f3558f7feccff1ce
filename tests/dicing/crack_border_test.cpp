// The border boxes that make level of detail crack-free (docs/architecture.md): each contains
// the true border curve over its segment and the segment's chord, each node contains its
// children, only curved patches get them, and a ray is stopped by one only when it enters it
// from outside.
#include <gtest/gtest.h>
#include <limits>
#include "core/transform.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "geometry/moving_patch.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// (u, v) of parameter t along border e (0: v=0, 1: u=1, 2: v=1, 3: u=0).
void borderParam(int e, float t, float& u, float& v) {
  u = e == 0 || e == 2 ? t : e == 1 ? 1.0f : 0.0f;
  v = e == 1 || e == 3 ? t : e == 2 ? 1.0f : 0.0f;
}

// A static dicing's segment boxes are computed on demand, per segment, without a tree: the
// walk prunes with them, so each must hold the true curve and every grid vertex of its segment
// (the chord ends of every finer level), and not depend on the level the patch was diced at.
TEST(BorderBoxes, ContainTheTrueCurveAndEveryVertexOfTheirSegment) {
  constexpr int m = 6;
  DiceBuffer dice(m), coarser(m);
  test::Random rnd(3);
  const auto teapot = test::loadTeapot();
  for (size_t p = 0; p < teapot.size(); p += 4) {
    const BezierPatch patch(teapot[p]);
    dice.dice(patch, m);
    coarser.dice(patch, m - 2);
    ASSERT_TRUE(dice.hasBorders());
    for (int e = 0; e < 4; ++e)
      for (int i = 0; i <= m; ++i)
        for (int j = 0; j < (1 << i); ++j) {
          const Box3 box = dice.borderNode(e, i, j);
          if (i <= m - 2) {
            const Box3 same = coarser.borderNode(e, i, j);
            ASSERT_TRUE(box.lo == same.lo && box.hi == same.hi) << p << " " << e << " " << i << " " << j;
          }
          const float t0 = float(j) / float(1 << i), t1 = float(j + 1) / float(1 << i);
          float u, v;
          for (int s = 0; s < 8; ++s) {
            borderParam(e, t0 + (t1 - t0) * rnd.uniform(), u, v);
            ASSERT_TRUE(box.contains(patch.evaluate(u, v).p)) << p << " " << e << " " << i << " " << j;
          }
          const int stride = 1 << (m - i), n = 1 << m;
          for (int g = j * stride; g <= (j + 1) * stride; ++g) {
            const int x = e == 0 || e == 2 ? g : e == 1 ? n : 0, y = e == 1 || e == 3 ? g : e == 2 ? n : 0;
            ASSERT_TRUE(box.contains(dice.position(x, y))) << p << " " << e << " " << i << " " << j << " " << g;
          }
        }
  }
}

TEST(BorderBoxes, PlanarPatchesHaveNone) {
  DiceBuffer dice(4);
  dice.dice(BilinearPatch({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}), 4);
  EXPECT_FALSE(dice.hasBorders());
  dice.dice(BezierPatch(test::loadTeapot()[0]), 4);
  EXPECT_TRUE(dice.hasBorders());
}

// A ray grazing just outside a curved patch's border, between the chord and the true curve at
// a coarse level: the micro-polygons miss, the border box catches it; a ray starting inside
// that box is not stopped by it; without closeBorders nothing changes.
TEST(BorderBoxes, CatchRaysThroughTheSlitOnlyFromOutside) {
  const BezierPatch patch(test::loadTeapot()[0]);
  DiceBuffer dice(4);
  dice.dice(patch, 4);
  test::Random rnd(9);
  int caught = 0;
  for (int r = 0; r < 4000; ++r) {
    const int e = rnd.below(4);
    float u, v;
    borderParam(e, rnd.uniform(0.2f, 0.8f), u, v);  // away from the corners, where two borders meet
    const SurfacePoint sp = patch.evaluate(u, v);
    const Vec3 n = normalize(sp.n);
    // Aim at the true border point from outside, along the surface normal.
    const Vec3 org = sp.p + n * 3.0f;
    const Vec3 dir = -n;
    BottomQuery closed;
    closed.closeBorders = true;
    GridHit plain, withBoxes;
    const bool hitPlain = dice.intersect(org, dir, 0.0f, kInf, 0, plain);
    const bool hitBoxes = dice.intersect(org, dir, 0.0f, kInf, 0, withBoxes, closed);
    if (hitPlain) {
      ASSERT_TRUE(hitBoxes);
      ASSERT_LE(withBoxes.t, plain.t);
    }
    if (!hitPlain && hitBoxes) {
      ++caught;
      EXPECT_TRUE(withBoxes.border);
      EXPECT_NEAR(length(withBoxes.ng), 1.0f, 1e-5f);
      // Starting at the hit point inside the box, the same ray is not stopped by it again.
      const Vec3 inside = org + dir * (withBoxes.t + 1e-4f);
      GridHit again;
      // (It may still enter another border's box, which it does from outside.)
      if (dice.intersect(inside, dir, 0.0f, kInf, 0, again, closed) && again.border && again.t < 1e-3f) {
        const bool sameBorder = e == 0 ? again.v == 0.0f : e == 1 ? again.u == 1.0f : e == 2 ? again.v == 1.0f
                                                                                      : again.u == 0.0f;
        EXPECT_FALSE(sameBorder) << r;
      }
    }
    EXPECT_EQ(dice.occluded(org, dir, 0.0f, kInf, 0, closed), hitBoxes)
        << r << " plain " << hitPlain << " t " << plain.t << " boxes t " << withBoxes.t << " border " << withBoxes.border;
  }
  EXPECT_GT(caught, 100);  // at level 0 a good part of the true border lies off the two triangles
}

TEST(BorderBoxes, MovingBordersInterpolateAndStillContainTheCurve) {
  auto at = [](const Transform& xf) {
    auto cp = test::loadTeapot()[5];
    for (auto& p : cp) p = xf.point(p);
    return std::make_shared<BezierPatch>(cp);
  };
  const MovingPatch mp({at(Transform{}), at(Transform::translate({0.5f, 0.2f, -0.3f}))}, {0.0f, 1.0f});
  DiceBuffer dice(3);
  dice.diceInterval(mp, 0, 3);
  ASSERT_TRUE(dice.hasBorders());
  test::Random rnd(4);
  int caught = 0;
  for (int r = 0; r < 3000; ++r) {
    const float alpha = rnd.uniform();
    const int e = rnd.below(4);
    float u, v;
    borderParam(e, rnd.uniform(), u, v);
    const Vec3 p = mp.evaluateAt(0, u, v).p * (1 - alpha) + mp.evaluateAt(1, u, v).p * alpha;
    const Vec3 n = normalize(mp.evaluateAt(0, u, v).n);
    BottomQuery q;
    q.alpha = alpha;
    q.closeBorders = true;
    GridHit h;
    // A ray along the normal through the interpolated true border point always hits.
    ASSERT_TRUE(dice.intersect(p + n * 2.0f, -n, 0.0f, kInf, rnd.below(4), h, q)) << r;
    caught += h.border;
  }
  EXPECT_GT(caught, 0);
}

}  // namespace
}  // namespace rayes
