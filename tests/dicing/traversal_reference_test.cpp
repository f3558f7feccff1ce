// The tree traversal against a brute-force reference with no tree at all: every micro-quad of
// the ray's level, accepted by the same pure function the traversal documents (watertight quad
// test, then the margin-padded corner-box slab test raising t to the box entry), nearest
// (t, quad index) wins. dice_traversal.cpp argues that culling by the tree never changes that
// minimum; this checks it bit for bit on every field, so a faster traversal (SIMD node tests,
// other child order, pruning) can be swapped in only if it is exactly as precise.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include "core/box.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "geometry/patch_math.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::sameBits;
constexpr float kInf = std::numeric_limits<float>::infinity();

Vec3 blended(const DiceBuffer& g, int x, int y, int stride, float s, float r) {
  const Vec3 n00 = g.normal(x, y), n10 = g.normal(x + stride, y), n01 = g.normal(x, y + stride),
             n11 = g.normal(x + stride, y + stride);
  return detail::unitOrZero((n00 * (1.0f - s) + n10 * s) * (1.0f - r) + (n01 * (1.0f - s) + n11 * s) * r);
}

// Written from the documented rule, not from the traversal's code.
bool bruteForce(const DiceBuffer& g, const Box3& patchBounds, Vec3 org, Vec3 dir, float tmin,
                float tmax, int rayLevel, GridHit& out) {
  if (!(tmin < tmax)) return false;
  WatertightRay wray;
  if (!makeWatertightRay(org, dir, wray)) return false;
  const int k = std::clamp(rayLevel, 0, g.level());
  const RayBoxQuery query(org, dir);
  const float farthest = maxComponent(vmax(vabs(patchBounds.lo - org), vabs(patchBounds.hi - org)));
  const float magnitude = maxComponent(vmax(vabs(patchBounds.lo), vabs(patchBounds.hi)));
  const float margin = gammaBound(16) * farthest + 0x1p-22f * magnitude;
  if (!std::isfinite(margin)) return false;
  const Vec3 pad{margin, margin, margin};
  const int stride = 1 << (g.level() - k);
  bool found = false;
  for (int y = 0; y < (1 << k); ++y)
    for (int x = 0; x < (1 << k); ++x) {
      const int i = x * stride, j = y * stride;
      const Vec3 p00 = g.position(i, j), p10 = g.position(i + stride, j), p01 = g.position(i, j + stride),
                 p11 = g.position(i + stride, j + stride);
      MicroQuadHit h;
      if (!intersectMicroQuad(wray, p00, p10, p01, p11, tmin, tmax, h)) continue;
      float tBox, tExit;
      if (!intersectBox(query, vmin(vmin(p00, p10), vmin(p01, p11)) - pad,
                        vmax(vmax(p00, p10), vmax(p01, p11)) + pad, tmin, tmax, tBox, tExit))
        continue;
      h.t = std::max(h.t, tBox);
      if (!(h.t < tmax)) continue;
      if (h.ng == Vec3{0, 0, 0}) {
        h.ng = blended(g, i, j, stride, h.s, h.r);
        if (h.ng == Vec3{0, 0, 0}) continue;
      }
      const uint32_t quad = (uint32_t(y) << k) | uint32_t(x);
      if (found && !(h.t < out.t || (h.t == out.t && quad < out.quad))) continue;
      found = true;
      const float inv = 1.0f / float(1u << k);
      out.t = h.t;
      out.u = (float(x) + h.s) * inv;
      out.v = (float(y) + h.r) * inv;
      out.quad = quad;
      out.ng = h.ng;
      const Vec3 ns = blended(g, i, j, stride, h.s, h.r);
      out.ns = ns == Vec3{0, 0, 0} ? h.ng : ns;
    }
  return found;
}

void expectSame(const DiceBuffer& g, const Box3& bounds, Vec3 org, Vec3 dir, float tmin, float tmax,
                int k, int& hits, const char* what) {
  GridHit a, b;
  const bool ha = g.intersect(org, dir, tmin, tmax, k, a);
  const bool hb = bruteForce(g, bounds, org, dir, tmin, tmax, k, b);
  ASSERT_EQ(ha, hb) << what << " k " << k;
  ASSERT_EQ(g.occluded(org, dir, tmin, tmax, k), hb) << what << " k " << k;
  if (!ha) return;
  ++hits;
  ASSERT_TRUE(sameBits(a.t, b.t)) << what << " k " << k << " " << a.t << " " << b.t;
  ASSERT_TRUE(sameBits(a.u, b.u)) << what;
  ASSERT_TRUE(sameBits(a.v, b.v)) << what;
  ASSERT_EQ(a.quad, b.quad) << what;
  ASSERT_TRUE(sameBits(a.ng, b.ng)) << what;
  ASSERT_TRUE(sameBits(a.ns, b.ns)) << what;
}

TEST(TraversalReference, RandomRaysOnTeapotPatchesEveryLevel) {
  const auto patches = test::loadTeapot();
  test::Random rng(71);
  DiceBuffer g(6);
  int hits = 0, rays = 0;
  for (int p : {0, 8, 16, 20, 28, 31}) {  // body, handle, spout, lid (pole), bottom
    for (auto [scale, offset] : {std::pair{1.0f, Vec3{0, 0, 0}}, {1e-3f, Vec3{0, 0, 0}}, {1e4f, Vec3{1e6f, 0, -1e6f}}}) {
      const BezierPatch bp(test::transformed(patches[p], scale, offset));
      const Box3 b = bp.bounds();
      const float r = length(b.extent());
      for (int m : {0, 1, 3, 6}) {
        g.dice(bp, m);
        for (int s = 0; s < 150; ++s, ++rays) {
          const Vec3 org = b.center() + rng.unitVector() * (r * rng.uniform(0.3f, 3.0f));
          const Vec3 target = s % 4 ? bp.evaluate(rng.uniform(), rng.uniform()).p
                                    : b.lo + b.extent() * Vec3{rng.uniform(), rng.uniform(), rng.uniform()};
          const Vec3 dir = (target - org) * rng.uniform(0.1f, 10.0f);
          const float tmin = s % 7 ? 0.0f : rng.uniform(0.0f, 0.5f) / rng.uniform(0.1f, 10.0f);
          const float tmax = s % 3 ? kInf : rng.uniform(0.2f, 2.0f);
          for (int k = 0; k <= m; ++k) expectSame(g, b, org, dir, tmin, tmax, k, hits, "random");
          // Origin inside the patch box (a secondary ray leaving the surface).
          expectSame(g, b, bp.evaluate(rng.uniform(), rng.uniform()).p, rng.unitVector(), 1e-4f * r, kInf,
                     rng.below(m + 1), hits, "from surface");
        }
      }
    }
  }
  EXPECT_GT(hits, rays / 2);
}

// Ties: rays through grid vertices and shared edges, axis-aligned rays (zero direction
// components, infinite reciprocals) and a flat grid where many boxes have zero thickness.
TEST(TraversalReference, VerticesEdgesAndAxisAlignedRays) {
  const auto patches = test::loadTeapot();
  test::Random rng(72);
  DiceBuffer g(5);
  int hits = 0;
  const BilinearPatch flat({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0});
  const BezierPatch body(patches[0]);
  for (const Patch* patch : {static_cast<const Patch*>(&flat), static_cast<const Patch*>(&body)}) {
    const Box3 b = patch->bounds();
    for (int m : {2, 5}) {
      g.dice(*patch, m);
      const int n = 1 << m;
      for (int s = 0; s < 400; ++s) {
        const int i = rng.below(n + 1), j = rng.below(n + 1);
        Vec3 target = g.position(i, j);
        if (s % 2 && i < n) target = (target + g.position(i + 1, j)) * 0.5f;  // an edge midpoint
        Vec3 dir = s % 5 == 0 ? Vec3{0, 0, -1} : s % 5 == 1 ? Vec3{0, -1, 0} : rng.unitVector();
        const Vec3 org = target - dir * (2.0f * length(b.extent()) + 1.0f);
        for (int k = 0; k <= m; ++k) expectSame(g, b, org, dir, 0.0f, kInf, k, hits, "vertex/edge");
      }
    }
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace rayes
