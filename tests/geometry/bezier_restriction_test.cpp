// Restriction of Bézier curves and patches (geometry/bezier_restriction.h): the shortcuts for
// degenerate intervals (border pieces) and for intervals starting at 0 give the values of the
// two full de Casteljau splits, so every bound computed through them is unchanged; and the
// restricted hull holds the patch over its rectangle.
#include <gtest/gtest.h>
#include <algorithm>
#include "geometry/bezier_restriction.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

using test::Random;

// The restriction as two full splits (always both), without shortcuts: the definition the shortcuts must match.
template <int n>
void fullRestriction(const Vec3 in[n], float a, float b, Vec3 out[n]) {
  Vec3 l[n], r[n], r2[n];
  detail::splitCurve<n>(in, a, l, r);
  const float t = a < 1 ? (b - a) / (1 - a) : 0.0f;
  detail::splitCurve<n>(r, std::clamp(t, 0.0f, 1.0f), out, r2);
}

template <int nu, int nv>
Box3 fullHull(const Vec3* c, float u0, float u1, float v0, float v1) {
  Vec3 rows[nu * nv];
  for (int j = 0; j < nv; ++j) fullRestriction<nu>(&c[j * nu], u0, u1, &rows[j * nu]);
  Box3 box;
  for (int i = 0; i < nu; ++i) {
    Vec3 col[nv], out[nv];
    for (int j = 0; j < nv; ++j) col[j] = rows[j * nu + i];
    fullRestriction<nv>(col, v0, v1, out);
    for (int j = 0; j < nv; ++j) box.extend(out[j]);
  }
  return box;
}

// Interval ends as a dicing's border pieces have them: dyadic, 0 and 1, and degenerate.
float dyadic(Random& rng) { return float(int(rng.uniform(0, 129))) / 128.0f; }

template <int nu, int nv>
void expectHullsMatch(Random& rng, int trials) {
  for (int k = 0; k < trials; ++k) {
    Vec3 c[nu * nv];
    for (Vec3& p : c) p = {rng.uniform(-1e3f, 1e3f), rng.uniform(-1, 1), rng.uniform(-1e-3f, 1e-3f)};
    float u0 = dyadic(rng), u1 = dyadic(rng), v0 = dyadic(rng), v1 = dyadic(rng);
    if (u0 > u1) std::swap(u0, u1);
    if (v0 > v1) std::swap(v0, v1);
    switch (k % 4) {  // every kind of border piece, and general rectangles
      case 0: v1 = v0; break;
      case 1: u1 = u0; break;
      case 2: v0 = v1 = float(k % 8 < 4); break;
      default: break;
    }
    const Box3 fast = detail::restrictedHull<nu, nv>(c, u0, u1, v0, v1);
    const Box3 full = fullHull<nu, nv>(c, u0, u1, v0, v1);
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(fast.lo[a], full.lo[a]) << "piece [" << u0 << "," << u1 << "]x[" << v0 << "," << v1 << "]";
      ASSERT_EQ(fast.hi[a], full.hi[a]) << "piece [" << u0 << "," << u1 << "]x[" << v0 << "," << v1 << "]";
    }
  }
}

TEST(BezierRestriction, CurveShortcutsGiveTheFullSplitsValues) {
  Random rng(5);
  for (int k = 0; k < 20000; ++k) {
    Vec3 in[4];
    for (Vec3& p : in) p = {rng.uniform(-10, 10), rng.uniform(-1e4f, 1e4f), rng.uniform(-1e-4f, 1e-4f)};
    float a = dyadic(rng), b = k % 3 == 0 ? a : dyadic(rng);
    if (k % 5 == 0) a = 0;
    if (a > b) std::swap(a, b);
    Vec3 fast[4], full[4];
    detail::restrictCurve<4>(in, a, b, fast);
    fullRestriction<4>(in, a, b, full);
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(fast[i][c], full[i][c]) << "[" << a << "," << b << "] point " << i;
  }
}

TEST(BezierRestriction, HullShortcutsGiveTheFullSplitsBoxes) {
  Random rng(6);
  expectHullsMatch<4, 4>(rng, 20000);  // a bicubic patch
  expectHullsMatch<3, 4>(rng, 20000);  // its hodographs
  expectHullsMatch<4, 3>(rng, 20000);
}

// The restricted hull contains the curve over the interval, including a point interval.
TEST(BezierRestriction, HullHoldsThePatchOverTheRectangle) {
  Random rng(7);
  for (int k = 0; k < 2000; ++k) {
    Vec3 c[16];
    for (Vec3& p : c) p = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
    float u0 = rng.uniform(0, 1), u1 = rng.uniform(0, 1), v0 = rng.uniform(0, 1), v1 = k % 2 ? v0 : rng.uniform(0, 1);
    if (u0 > u1) std::swap(u0, u1);
    if (v0 > v1) std::swap(v0, v1);
    const Box3 box = detail::restrictedHull<4, 4>(c, u0, u1, v0, v1);
    const float u = u0 + (u1 - u0) * rng.uniform(0, 1), v = v0 + (v1 - v0) * rng.uniform(0, 1);
    Vec3 row[4];
    for (int j = 0; j < 4; ++j) row[j] = detail::deCasteljauPoint<4>(&c[j * 4], u);
    const Vec3 p = detail::deCasteljauPoint<4>(row, v);
    // Both sides round: each of the hull's splits and the point's triangles is at most 36
    // roundings of values within the unit-sized hull, 2^-24 each.
    const float slack = 2 * 36 * 0x1p-24f;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p[a], box.lo[a] - slack);
      EXPECT_LE(p[a], box.hi[a] + slack);
    }
  }
}

}  // namespace
}  // namespace rayes
