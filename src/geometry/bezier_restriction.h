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
//
// A crack-closing region's radius needs the boxes of up to 128 consecutive pieces of one border
// (DiceBuffer::borderRadius). borderPieceHulls makes them all from one restriction of the
// border curve, halving it `split` times, instead of two splits of the whole patch per piece:
// other bits than restrictedHull's, with a rounding bound of its own (borderPieceRoundings).
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

// The border curve of the tensor-product patch with (nu x nv) control points c[j * nu + i]:
// border e (0: v = 0, 1: u = 1, 2: v = 1, 3: u = 0, each with its parameter increasing along u
// or v) is the Bézier curve of the patch's edge row or column, copied exactly. Returns its
// number of control points.
template <int nu, int nv>
int borderCurve(const Vec3* c, int e, Vec3 out[4]) {
  static_assert(nu <= 4 && nv <= 4);
  if (e == 0 || e == 2) {
    const int j = e == 0 ? 0 : nv - 1;
    for (int i = 0; i < nu; ++i) out[i] = c[j * nu + i];
    return nu;
  }
  const int i = e == 3 ? 0 : nu - 1;
  for (int j = 0; j < nv; ++j) out[j] = c[j * nu + i];
  return nv;
}

// Roundings (each of the control points' magnitude) that separate a borderPieceHulls box from
// the exact control points' hull: the restriction to [a, b], two splits of 3 levels of 3
// roundings with the rounded parameter (24, as restrictedHull's per direction), and 9 per
// halving (3 levels; the product by 1/2 is exact). The border curve itself is exact.
constexpr int borderPieceRoundings(int split) { return 24 + 9 * split; }

// The boxes of the 2^split equal pieces of the degree-(n-1) curve `in` restricted to [a, b],
// in order along the curve: out[i] holds the control points of the i-th piece.
template <int n>
void borderPieceHulls(const Vec3 in[n], float a, float b, int split, Box3* out) {
  Vec3 segment[n];
  restrictCurve<n>(in, a, b, segment);
  // Depth first, left before right, so that out[] comes in order; the stack holds the right
  // halves still to do, at most one per level.
  struct Pending { Vec3 p[n]; int depth; };
  Pending stack[16];
  int sp = 0;
  Pending cur;
  for (int i = 0; i < n; ++i) cur.p[i] = segment[i];
  cur.depth = 0;
  int next = 0;
  for (;;) {
    while (cur.depth < split) {
      Pending right;
      splitCurve<n>(cur.p, 0.5f, cur.p, right.p);
      right.depth = ++cur.depth;
      stack[sp++] = right;
    }
    Box3 box;
    for (int i = 0; i < n; ++i) box.extend(cur.p[i]);
    out[next++] = box;
    if (sp == 0) return;
    cur = stack[--sp];
  }
}

// Dispatch on the number of control points of a border curve (borderCurve's result).
inline void borderPieceHulls(const Vec3* in, int n, float a, float b, int split, Box3* out) {
  switch (n) {
    case 2: borderPieceHulls<2>(in, a, b, split, out); break;
    case 3: borderPieceHulls<3>(in, a, b, split, out); break;
    default: borderPieceHulls<4>(in, a, b, split, out); break;
  }
}

}  // namespace rayes::detail
