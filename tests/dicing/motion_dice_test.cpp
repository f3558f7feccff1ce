// Motion blur at the bottom level (thesis §6.3): a moving patch diced over one time interval
// is intersected as the point-wise interpolation of its two samples. Checked against a
// tree-free reference on the interpolated vertices, bit for bit, at every level, and at the
// interval's ends against the static dicing of each sample.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include "core/box.h"
#include "core/transform.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "geometry/moving_patch.h"
#include "support/moving_teapot.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::movingTeapotPatch;
using test::sameBits;
using test::teapotPatchAt;
constexpr float kInf = std::numeric_limits<float>::infinity();

// Points of the interval's surface: a random sample point interpolated between both samples.
TEST(MovingDice, InterpolatedBoundsContainEveryInterpolatedPoint) {
  const auto mp = movingTeapotPatch();
  test::Random rnd(5);
  for (int k = 0; k < 2000; ++k) {
    const float u = rnd.uniform(), v = rnd.uniform(), t = rnd.uniform();
    const TimeInterval w = timeInterval(*mp, t);
    const Vec3 a = mp->evaluateAt(w.interval, u, v).p, b = mp->evaluateAt(w.interval + 1, u, v).p;
    EXPECT_TRUE(mp->bounds().contains(a * (1 - w.alpha) + b * w.alpha));
  }
}

// Tree-free reference for a moving dicing: every quad of level k made of the interpolated
// vertices (a * (1 - alpha) + b * alpha), the documented acceptance rule, nearest (t, quad).
bool reference(const DiceBuffer& a, const DiceBuffer& b, const Box3& bounds, float alpha, Vec3 org, Vec3 dir,
               int k, GridHit& out) {
  WatertightRay wray;
  if (!makeWatertightRay(org, dir, wray)) return false;
  const RayBoxQuery query(org, dir);
  const float farthest = maxComponent(vmax(vabs(bounds.lo - org), vabs(bounds.hi - org)));
  const float magnitude = maxComponent(vmax(vabs(bounds.lo), vabs(bounds.hi)));
  const float margin = gammaBound(16) * farthest + 0x1p-22f * magnitude;
  const Vec3 pad{margin, margin, margin};
  const float w0 = 1.0f - alpha, w1 = alpha;
  auto P = [&](int i, int j) { return a.position(i, j) * w0 + b.position(i, j) * w1; };
  const int stride = 1 << (a.level() - k);
  bool found = false;
  for (int y = 0; y < (1 << k); ++y)
    for (int x = 0; x < (1 << k); ++x) {
      const int i = x * stride, j = y * stride;
      const Vec3 p00 = P(i, j), p10 = P(i + stride, j), p01 = P(i, j + stride), p11 = P(i + stride, j + stride);
      MicroQuadHit h;
      if (!intersectMicroQuad(wray, p00, p10, p01, p11, 0.0f, kInf, h)) continue;
      float tBox, tExit;
      if (!intersectBox(query, vmin(vmin(p00, p10), vmin(p01, p11)) - pad, vmax(vmax(p00, p10), vmax(p01, p11)) + pad,
                        0.0f, kInf, tBox, tExit))
        continue;
      h.t = std::max(h.t, tBox);
      const uint32_t quad = (uint32_t(y) << k) | uint32_t(x);
      if (found && !(h.t < out.t || (h.t == out.t && quad < out.quad))) continue;
      found = true;
      out.t = h.t;
      out.quad = quad;
    }
  return found;
}

TEST(MovingDice, TraversalEqualsTheInterpolatedReferenceAtEveryLevel) {
  const auto mp = movingTeapotPatch();
  constexpr int m = 5;
  DiceBuffer moving(m), fine(m + 2), a(m), b(m);
  test::Random rnd(17);
  int hits = 0;
  for (int interval = 0; interval < 2; ++interval) {
    moving.diceInterval(*mp, interval, m);
    fine.diceInterval(*mp, interval, m + 2);
    EXPECT_TRUE(moving.moving());
    a.dice(mp->sample(interval), m);
    b.dice(mp->sample(interval + 1), m);
    for (int r = 0; r < 600; ++r) {
      const float alpha = r % 7 == 0 ? 0.0f : r % 7 == 1 ? 1.0f : rnd.uniform();
      const Vec3 target = mp->evaluateAt(interval, rnd.uniform(), rnd.uniform()).p * (1 - alpha) +
                          mp->evaluateAt(interval + 1, rnd.uniform(), rnd.uniform()).p * alpha;
      const Vec3 org = target + rnd.unitVector() * 6.0f;
      const Vec3 dir = target - org + rnd.unitVector() * 0.05f;
      const int k = rnd.below(m + 1);
      GridHit got, ref, finer;
      BottomQuery q;
      q.alpha = alpha;
      const bool hit = moving.intersect(org, dir, 0.0f, kInf, k, got, q);
      ASSERT_EQ(hit, reference(a, b, mp->bounds(), alpha, org, dir, k, ref)) << r;
      // The same ray at the same level on a finer dicing: the same hit (order independence).
      ASSERT_EQ(hit, fine.intersect(org, dir, 0.0f, kInf, k, finer, q)) << r;
      if (!hit) continue;
      ++hits;
      ASSERT_TRUE(sameBits(got.t, ref.t)) << r << " " << got.t << " " << ref.t;
      ASSERT_EQ(got.quad, ref.quad) << r;
      ASSERT_TRUE(sameBits(got.t, finer.t)) << r;
      ASSERT_EQ(got.quad, finer.quad) << r;
      ASSERT_TRUE(sameBits(got.ns, finer.ns)) << r;
      // At the interval's ends: exactly the static dicing of that sample.
      if (alpha == 0.0f || alpha == 1.0f) {
        GridHit still;
        ASSERT_TRUE((alpha == 0.0f ? a : b).intersect(org, dir, 0.0f, kInf, k, still));
        ASSERT_TRUE(sameBits(got.t, still.t));
        ASSERT_EQ(got.quad, still.quad);
        ASSERT_TRUE(sameBits(got.ng, still.ng));
      }
      ASSERT_EQ(moving.occluded(org, dir, 0.0f, kInf, k, q), true);
    }
  }
  EXPECT_GT(hits, 600);
}

TEST(MovingDice, StaticPatchesUseOneSampleAndTheSecondGridIsAllocatedOnFirstUse) {
  DiceBuffer buffer(4);
  const size_t before = buffer.bytesAllocated();
  buffer.diceInterval(*teapotPatchAt(Transform{}), 0, 4);  // static: plain dice
  EXPECT_FALSE(buffer.moving());
  EXPECT_EQ(buffer.bytesAllocated(), before);
  buffer.diceInterval(*movingTeapotPatch(), 1, 4);
  EXPECT_TRUE(buffer.moving());
  const size_t segments = 4 * ((size_t(2) << 4) - 1);
  // The border segments' boxes, radii and stamps are shared, not per sample; a moving dicing
  // adds a border tree per sample.
  const size_t shared = segments * (2 * sizeof(Box3) + 2 * sizeof(double) + 8);
  EXPECT_EQ(buffer.bytesAllocated(), 2 * before - shared + 2 * segments * sizeof(Box3));
  buffer.dice(*movingTeapotPatch(), 3);  // sample 0 alone
  EXPECT_FALSE(buffer.moving());
  EXPECT_THROW(buffer.diceInterval(*movingTeapotPatch(), 2, 4), std::invalid_argument);
}

}  // namespace
}  // namespace rayes
