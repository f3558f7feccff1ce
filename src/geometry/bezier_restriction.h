// Restriction of Bézier curves and tensor-product patches to a parameter interval or rectangle:
// the control points of the piece over [a, b] by two de Casteljau splits, and the box of a
// patch's control points restricted to a rectangle, which by the convex hull property holds the
// patch over it. One implementation for every Bézier bound (BezierPatch::boundsOver, the
// hodographs of DisplacedPatch::normalRangeOver).
//
// Border pieces make most of the calls (crack-closing regions bound the border curve over
// hundreds of pieces per dicing), and a border is a degenerate rectangle: u0 == u1 or v0 == v1.
// The shortcuts below skip work whose result is known exactly -- a split at t = 0 leaves the
// points unchanged, and a restriction to [a, a] gives n copies of the split's point at a -- and
// compute what remains with the same operations in the same order, so every box has the values
// the two full splits give (a split at t = 0 can turn a -0 coordinate into +0, nothing else;
// tests/geometry/bezier_restriction_test.cpp).
#pragma once
#include <algorithm>
#include "core/box.h"
#include "core/vec.h"

namespace rayes::detail {

// The point at t of the degree-(n-1) curve p: the last point of the de Casteljau triangle, the
// same operations a split at t performs.
template <int n>
Vec3 deCasteljauPoint(const Vec3 p[n], float t) {
  Vec3 w[n];
  for (int i = 0; i < n; ++i) w[i] = p[i];
  for (int r = 0; r + 1 < n; ++r)
    for (int i = 0; i + 1 < n - r; ++i) w[i] = w[i] + (w[i + 1] - w[i]) * t;
  return w[0];
}

// One de Casteljau split of the degree-(n-1) curve p at t: left covers [0, t], right [t, 1].
template <int n>
void splitCurve(const Vec3 p[n], float t, Vec3 left[n], Vec3 right[n]) {
  Vec3 w[n];
  for (int i = 0; i < n; ++i) w[i] = p[i];
  for (int r = 0; r < n; ++r) {
    left[r] = w[0];
    right[n - 1 - r] = w[n - 1 - r];
    for (int i = 0; i + 1 < n - r; ++i) w[i] = w[i] + (w[i + 1] - w[i]) * t;
  }
}

// Control points of the degree-(n-1) Bézier curve in[0..n-1] restricted to [a, b] (a <= b):
// two de Casteljau splits. Exact intervals of zero width give n copies of the point at a.
template <int n>
void restrictCurve(const Vec3 in[n], float a, float b, Vec3 out[n]) {
  if (a == b) {  // the second split is at t = 0: n copies of the first split's point at a
    const Vec3 p = a == 0.0f ? in[0] : deCasteljauPoint<n>(in, a);
    for (int i = 0; i < n; ++i) out[i] = p;
    return;
  }
  Vec3 l[n], r[n], r2[n];
  const Vec3* from = in;  // a split at 0 gives the curve itself as its right part
  if (a != 0.0f) {
    splitCurve<n>(in, a, l, r);  // r covers [a, 1]
    from = r;
  }
  const float t = a < 1 ? (b - a) / (1 - a) : 0.0f;
  splitCurve<n>(from, std::clamp(t, 0.0f, 1.0f), out, r2);  // out covers [a, b]
}

// The box of the Bézier patch with (nu x nv) control points c[j * nu + i] restricted to the
// rectangle [u0, u1] x [v0, v1].
template <int nu, int nv>
Box3 restrictedHull(const Vec3* c, float u0, float u1, float v0, float v1) {
  Box3 box;
  if (u0 == u1) {  // every row restricts to copies of its point at u0: one column is all
    Vec3 col[nv], out[nv];
    for (int j = 0; j < nv; ++j) col[j] = u0 == 0.0f ? c[j * nu] : deCasteljauPoint<nu>(&c[j * nu], u0);
    restrictCurve<nv>(col, v0, v1, out);
    for (int j = 0; j < nv; ++j) box.extend(out[j]);
    return box;
  }
  Vec3 rows[nu * nv];
  const int rowsNeeded = v0 == v1 && v0 == 0.0f ? 1 : nv;  // at v = 0 a column is its first point
  for (int j = 0; j < rowsNeeded; ++j) restrictCurve<nu>(&c[j * nu], u0, u1, &rows[j * nu]);
  for (int i = 0; i < nu; ++i) {
    if (v0 == v1) {  // the column restricts to copies of its point at v0
      Vec3 col[nv];
      for (int j = 0; j < rowsNeeded; ++j) col[j] = rows[j * nu + i];
      box.extend(v0 == 0.0f ? col[0] : deCasteljauPoint<nv>(col, v0));
      continue;
    }
    Vec3 col[nv], out[nv];
    for (int j = 0; j < nv; ++j) col[j] = rows[j * nu + i];
    restrictCurve<nv>(col, v0, v1, out);
    for (int j = 0; j < nv; ++j) box.extend(out[j]);
  }
  return box;
}

}  // namespace rayes::detail
