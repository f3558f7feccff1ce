// The edge-sign test of the 4 sibling micro-quads of a quad-tree node in one SSE pass: a filter
// in front of intersectMicroQuad (micro_quad.h) that the traversal runs once per node whose
// children are micro-quads, so that the full test (double fallback, t, normals) runs only on
// the quads it keeps. Exact: it computes the watertight test's projections and edge values with
// the same IEEE operations on the same operands, lane by lane (-ffp-contract=off), so it clears
// a quad's bit only where intersectMicroQuad would return false. Stateless, thread-safe.
#pragma once
#include <emmintrin.h>
#include <cstddef>
#include "dicing/micro_quad.h"

namespace rayes {
namespace detail {

// Vertex v in the sheared frame as lanes (x, y, -, -): project<KX, KY, KZ>'s operations, the
// origin subtracted per picked axis (the same operation as subtracting it whole).
template <int KX, int KY, int KZ>
[[gnu::always_inline]] inline __m128 project2(const Vec3& v, __m128 org, __m128 shear) {
  // x, y by one 8-byte load (__m128i may alias floats), z by a 4-byte one: no read past the vertex.
  const __m128 lo = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&v.x)));
  const __m128 p = _mm_movelh_ps(lo, _mm_load_ss(&v.z));
  const __m128 d = _mm_sub_ps(p, org);
  const __m128 xy = _mm_shuffle_ps(d, d, _MM_SHUFFLE(KZ, KZ, KY, KX));
  const __m128 zz = _mm_shuffle_ps(d, d, _MM_SHUFFLE(KZ, KZ, KZ, KZ));
  return _mm_sub_ps(xy, _mm_mul_ps(shear, zz));
}

// edgeFunction lane by lane: q.x * p.y - q.y * p.x.
inline __m128 edgeFunction4(__m128 px, __m128 py, __m128 qx, __m128 qy) {
  return _mm_sub_ps(_mm_mul_ps(qx, py), _mm_mul_ps(qy, px));
}

// All ones where hitTriangle rejects on its edge signs alone: no edge value is 0 and they have
// both signs (ordered compares, so a NaN lane is not rejected, as in hitTriangle).
inline __m128 edgesReject4(__m128 u, __m128 v, __m128 w) {
  const __m128 zero = _mm_setzero_ps();
  const __m128 anyZero = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(v, zero)), _mm_cmpeq_ps(w, zero));
  const __m128 anyNeg = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(v, zero)), _mm_cmplt_ps(w, zero));
  const __m128 anyPos = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(v, zero)), _mm_cmpgt_ps(w, zero));
  return _mm_andnot_ps(anyZero, _mm_and_ps(anyNeg, anyPos));
}

template <int KX, int KY, int KZ>
[[gnu::always_inline]] inline int quadsMayHit4On(const WatertightRay& ray, const Vec3* v, size_t dx, size_t dy) {
  const __m128 org = _mm_setr_ps(ray.org.x, ray.org.y, ray.org.z, 0.0f);
  const __m128 shear = _mm_setr_ps(ray.sx, ray.sy, 0.0f, 0.0f);
  __m128 q[9];  // (x, y, -, -) of the 3 x 3 vertices, row by row
  for (size_t j = 0; j < 3; ++j)
    for (size_t i = 0; i < 3; ++i) q[3 * j + i] = project2<KX, KY, KZ>(v[j * dy + i * dx], org, shear);
  // Pairs of horizontal neighbours as (x_i, x_i+1, y_i, y_i+1); two pairs a row apart give a
  // corner's x and y over the 4 quads (Z order: quad c has corner p00 at vertex (c & 1, c >> 1)).
  __m128 pair[6];
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 2; ++i) pair[2 * j + i] = _mm_unpacklo_ps(q[3 * j + i], q[3 * j + i + 1]);
  auto corner = [&](int i, int j, __m128& x, __m128& y) {  // lanes: the quads' corner (+i, +j)
    x = _mm_movelh_ps(pair[2 * j + i], pair[2 * (j + 1) + i]);
    y = _mm_movehl_ps(pair[2 * (j + 1) + i], pair[2 * j + i]);
  };
  __m128 ax, ay, bx, by, cx, cy, dxv, dyv;  // a = p00, b = p10, c = p01, d = p11, as intersectMicroQuadOn
  corner(0, 0, ax, ay);
  corner(1, 0, bx, by);
  corner(0, 1, cx, cy);
  corner(1, 1, dxv, dyv);
  // hitTriangle(a, b, d) and hitTriangle(a, d, c): U = edge(b, c), V = edge(c, a), W = edge(a, b)
  // of each, with the same operands in the same order.
  const __m128 reject1 = edgesReject4(edgeFunction4(bx, by, dxv, dyv), edgeFunction4(dxv, dyv, ax, ay),
                                      edgeFunction4(ax, ay, bx, by));
  const __m128 reject2 = edgesReject4(edgeFunction4(dxv, dyv, cx, cy), edgeFunction4(cx, cy, ax, ay),
                                      edgeFunction4(ax, ay, dxv, dyv));
  return ~_mm_movemask_ps(_mm_and_ps(reject1, reject2)) & 0xf;
}

}  // namespace detail

// The 4 micro-quads of the 3 x 3 vertices v[j * dy + i * dx] (i, j in 0..2), quad c (Z order)
// with corner p00 at vertex (c & 1, c >> 1): bit c clear only if intersectMicroQuad(ray, its
// corners, ...) returns false for every (tmin, tmax), i.e. both triangles' edge values, computed
// with the same operations on the same operands (so the same bits), have both signs and none is
// 0. The traversal drops the quads it clears before they reach its stack: of the ~4 quads a ray
// reaches on bench_dicing_embree's grid, ~1 has a triangle whose edge signs agree. Each vertex
// is projected once with 4-wide ops and regrouped by shuffles; gathering the quads' corners
// coordinate by coordinate (_mm_setr_ps) cost 220 instructions a call, more than it saved
// (callgrind, bench/history/2026-11.md, "The bottom level's second session").
[[gnu::always_inline]] inline int quadsMayHit4(const WatertightRay& ray, const Vec3* v, size_t dx, size_t dy) {
  using detail::quadsMayHit4On;
  switch (ray.axes) {
    case 0: return quadsMayHit4On<1, 2, 0>(ray, v, dx, dy);
    case 1: return quadsMayHit4On<2, 1, 0>(ray, v, dx, dy);
    case 2: return quadsMayHit4On<2, 0, 1>(ray, v, dx, dy);
    case 3: return quadsMayHit4On<0, 2, 1>(ray, v, dx, dy);
    case 4: return quadsMayHit4On<0, 1, 2>(ray, v, dx, dy);
    default: return quadsMayHit4On<1, 0, 2>(ray, v, dx, dy);
  }
}

}  // namespace rayes
