// Arithmetic shared by the patch kinds, kept in one place because watertight seams depend on
// two different patches running *exactly* the same float operations on a shared border.
//
// Canonical boundary evaluation: a border curve is evaluated from its control points taken in
// a canonical order (the lexicographically smaller of the sequence and its reverse), at t or
// 1-t accordingly. For the dyadic parameters of a dicing 1-t is exact, so two patches that
// share a border -- whatever their orientations -- produce bit-identical border vertices.
// Endpoints come out exactly as the corner control points (weights 1 and 0), so corners agree
// between the two borders that meet there and between neighbours.
#pragma once
#include <algorithm>
#include <cmath>
#include "core/box.h"
#include "core/vec.h"

namespace rayes::detail {

// -1, 0, 1: lexicographic order of (x, y, z).
inline int lexCompare(Vec3 a, Vec3 b) {
  for (int k = 0; k < 3; ++k) {
    if (a[k] < b[k]) return -1;
    if (a[k] > b[k]) return 1;
  }
  return 0;
}

// Bernstein weights of degree 3, one formula for every caller.
inline void cubicBasis(float t, float b[4]) {
  const float s = 1.0f - t;
  b[0] = s * s * s;
  b[1] = 3.0f * t * s * s;
  b[2] = 3.0f * t * t * s;
  b[3] = t * t * t;
}

// The Bernstein blend of four points with weights b (cubicBasis): one expression for every
// caller, so rows, positions and derivatives computed in different places round alike.
inline Vec3 bernsteinBlend(const Vec3 p[4], const float b[4]) { return p[0] * b[0] + p[1] * b[1] + p[2] * b[2] + p[3] * b[3]; }

// Derivative of a cubic Bézier in hodograph form, 3 * sum_k B2_k(t) (p[k+1] - p[k]): exactly
// zero on a collapsed row (a pole), where the weighted sum sum_k B3'_k(t) p[k] would leave
// rounding noise large enough to pass for a real (and wrong) normal.
inline Vec3 cubicDerivative(const Vec3 p[4], float t) {
  const float s = 1.0f - t;
  return ((p[1] - p[0]) * (s * s) + (p[2] - p[1]) * (2.0f * t * s) + (p[3] - p[2]) * (t * t)) * 3.0f;
}

// Second derivative of a cubic Bézier, 6 * sum_k B1_k(t) (second differences): the differences
// of the hodograph's control points, so again exactly zero on a collapsed row.
inline Vec3 cubicSecondDerivative(const Vec3 p[4], float t) {
  const Vec3 d0 = p[1] - p[0], d1 = p[2] - p[1], d2 = p[3] - p[2];
  return ((d1 - d0) * (1.0f - t) + (d2 - d1) * t) * 6.0f;
}

inline Vec3 cubicBezier(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, float t) {
  const float s = 1.0f - t;
  return p0 * (s * s * s) + p1 * (3.0f * t * s * s) + p2 * (3.0f * t * t * s) + p3 * (t * t * t);
}

// The cubic relative to its first control point: the blend's rounding is then a few ulps of
// the curve's own extent, not of its distance from the origin; only the final addition rounds
// at the origin's scale (half an ulp). Endpoints are returned exactly.
inline Vec3 anchoredCubic(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, float t) {
  if (t == 0.0f) return p0;
  if (t == 1.0f) return p3;
  return p0 + cubicBezier(Vec3{0, 0, 0}, p1 - p0, p2 - p0, p3 - p0, t);
}

// Rounding of a point of a Bézier patch or border evaluated this way (anchoredCubic, or
// BezierPatch's blends of its anchored control points): two Bernstein blends of 4 points,
// each 4 products and 3 sums with weights off by at most 5 roundings (3 t s s), on values at
// most 2 L in magnitude (L: the largest anchored coordinate): gamma(24) * 2 L, plus the final
// addition of the anchor (half an ulp of the point, Box3::grownBy's own term).
inline float anchoredEvaluationError(float anchoredMagnitude) {
  return gammaBound(24) * 2.0f * anchoredMagnitude;
}

// The border curve with control points p0..p3 (in the caller's orientation) at t.
inline Vec3 canonicalCubic(Vec3 p0, Vec3 p1, Vec3 p2, Vec3 p3, float t) {
  int c = lexCompare(p0, p3);
  if (c == 0) c = lexCompare(p1, p2);
  if (c < 0) return anchoredCubic(p0, p1, p2, p3, t);
  if (c > 0) return anchoredCubic(p3, p2, p1, p0, 1.0f - t);
  // A palindrome: both orientations are the same sequence, and the curve is symmetric, so
  // fold t onto [0, 1/2] to make t and 1-t run the same operations.
  return anchoredCubic(p0, p1, p2, p3, std::min(t, 1.0f - t));
}

inline Vec3 lerp(Vec3 a, Vec3 b, float t) { return a * (1.0f - t) + b * t; }

// Rounding of a bilinear point lerp(lerp(a, b, u), lerp(c, d, u), v) on corners of magnitude
// at most M: per lerp 1 - t, two products and a sum (4 roundings, weights summing to 1), two
// levels: gamma(8) * M. Relative to the origin, not the patch: bilinear patches need no border
// regions, so this only widens their leaf box.
inline float bilinearEvaluationError(float magnitude) { return gammaBound(8) * magnitude; }

// The straight border a-b at t, in canonical orientation.
inline Vec3 canonicalLerp(Vec3 a, Vec3 b, float t) {
  const int c = lexCompare(a, b);
  if (c < 0) return lerp(a, b, t);
  if (c > 0) return lerp(b, a, 1.0f - t);
  return a;
}

// The patch normal at (u, v), finite and non-zero wherever the patch is not degenerate as a
// whole. At a pole or collapsed edge dP/du x dP/dv vanishes; we then take the normal at the
// parameter nudged toward the patch centre by 2^-12, 2^-6, 2^-2 of the way. We chose the nudge
// over the analytic limit (second derivative x the other first derivative) because it handles
// every kind of degeneracy -- collapsed rows, coincident inner control points, cusps -- with
// one rule, and near a pole the normal converges to the limit anyway. `tiny` is the magnitude
// below which a normal counts as degenerate (the patch kinds use 1e-6 * size^2).
template <class NormalAt>
Vec3 nonDegenerateNormal(NormalAt normalAt, Vec3 n, float u, float v, float tiny) {
  static constexpr float kNudge[3] = {1.0f / 4096.0f, 1.0f / 64.0f, 1.0f / 4.0f};
  for (float d : kNudge) {
    if (maxComponent(vabs(n)) > tiny) return n;
    n = normalAt(u + (0.5f - u) * d, v + (0.5f - v) * d);
  }
  return n;  // The whole patch is degenerate: zero, and the dice buffer falls back to ng.
}

// Magnitude threshold for nonDegenerateNormal from the patch's size (longest side of its box).
inline float degenerateNormalThreshold(float size) { return 1e-6f * size * size; }

}  // namespace rayes::detail

namespace rayes::detail {

// Unit vector along n, or zero when n is zero or not finite. Scaling by the largest component
// first keeps tiny (1e-3-scaled geometry, squared) and huge normals from under/overflowing.
inline Vec3 unitOrZero(Vec3 n) {
  const float m = maxComponent(vabs(n));
  if (!(m > 0.0f) || !std::isfinite(m)) return {0, 0, 0};
  n = n * (1.0f / m);
  return n * (1.0f / std::sqrt(dot(n, n)));
}

}  // namespace rayes::detail
