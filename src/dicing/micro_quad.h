// The one ray / micro-quad test, used by both DiceBuffer::intersect and ::occluded.
//
// A micro-quad (p00, p10, p01, p11) is two triangles split along the fixed diagonal p00-p11:
// (p00, p10, p11) and (p00, p11, p01), both counter-clockwise in (u, v), so every edge shared
// inside a grid is walked in opposite directions by its two triangles.
//
// Triangle test: the watertight test of Woop, Benthin and Wald (JCGT 2013). Vertices are
// translated to the ray origin and sheared so the ray becomes the +z axis (per-ray constants
// computed once); the 2D edge function of an edge P->Q is Q.x*P.y - Q.y*P.x, which the two
// triangles sharing the edge compute from the same operands, so the values are exact
// negations (or equal, for a neighbour patch of opposite orientation). Rounding is monotone,
// so a float edge value is either of the right sign or exactly 0; only then is it recomputed
// in double, where the products are exact. Hence a ray through a shared edge or vertex is
// claimed by at least one triangle. Both faces count (no culling). Requires -ffp-contract=off.
//
// Every division happens only after the sign tests pass and is guarded: no NaN or Inf leaves
// this file. Stateless, thread-safe.
#pragma once
#include <algorithm>
#include "core/vec.h"
#include "geometry/patch_math.h"

namespace rayes {

// Per-ray constants of the watertight test.
struct WatertightRay {
  Vec3 org;
  int kx = 0, ky = 1, kz = 2;  // axis permutation: kz is the dominant direction axis
  float sx = 0, sy = 0, sz = 1;  // shear
  float ox = 0, oy = 0, oz = 0;  // org[kx], org[ky], org[kz]: project() subtracts only these
  int axes = 4;                  // (kx, ky, kz) as one of six: 2 * kz + (kx != (kz + 1) % 3)
};

// False (no hit possible) for a non-finite origin or a zero, non-finite or denormal direction.
bool makeWatertightRay(Vec3 org, Vec3 dir, WatertightRay& ray);

struct MicroQuadHit {
  float t = 0;
  float s = 0, r = 0;  // local quad coordinates in [0,1]^2 (s along p00->p10, r along p00->p01)
  Vec3 ng;             // unit geometric normal (zero: both triangles degenerate, see below)
};

namespace detail {

// A vertex in the ray's sheared frame.
struct Projected {
  float x, y, z;
};

// The axes are template arguments (intersectMicroQuad switches once per quad on ray.axes): the
// per-ray index through Vec3::operator[] compiled to compare-and-select chains that were 17 % of
// the bottom level's instructions (callgrind on bench_dicing_embree, bench/history/2026-11.md,
// "Where the bottom level's instructions go"). Subtracting the origin per picked axis is the
// same operation, so the same bits, as subtracting it whole and picking after.
template <int KX, int KY, int KZ>
inline Projected project(const WatertightRay& ray, Vec3 p) {
  const float c[3] = {p.x, p.y, p.z};
  const float az = c[KZ] - ray.oz;
  return {(c[KX] - ray.ox) - ray.sx * az, (c[KY] - ray.oy) - ray.sy * az, ray.sz * az};
}

inline float edgeFunction(const Projected& p, const Projected& q) { return q.x * p.y - q.y * p.x; }

// The rare path: some edge value rounded to exactly 0.
bool hitTriangleDouble(const Projected& a, const Projected& b, const Projected& c, float tmin,
                       float tmax, float& t, float& wb, float& wc);

// Unit normal of (a, b, c) computed in double; false for a degenerate triangle.
bool unitTriangleNormal(Vec3 a, Vec3 b, Vec3 c, Vec3& n);

// Hit with t in (tmin, tmax); wb, wc are the barycentric weights of b and c.
inline bool hitTriangle(const Projected& a, const Projected& b, const Projected& c, float tmin,
                        float tmax, float& t, float& wb, float& wc) {
  const float U = edgeFunction(b, c), V = edgeFunction(c, a), W = edgeFunction(a, b);
  if (U == 0.0f || V == 0.0f || W == 0.0f) return hitTriangleDouble(a, b, c, tmin, tmax, t, wb, wc);
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;
  // U, V, W share det's sign, so t is a convex blend of the vertex depths and V/det, W/det lie
  // in [0,1]: the divisions stay finite even for a denormal det. A NaN fails the range test.
  t = (U * a.z + V * b.z + W * c.z) / det;
  if (!(t > tmin && t < tmax)) return false;
  wb = V / det;
  wc = W / det;
  return true;
}

// intersectMicroQuad for the ray's axes (KX, KY, KZ) = (ray.kx, ray.ky, ray.kz).
template <int KX, int KY, int KZ>
[[gnu::always_inline]] inline bool intersectMicroQuadOn(const WatertightRay& ray, Vec3 p00, Vec3 p10, Vec3 p01,
                                                        Vec3 p11, float tmin, float tmax, MicroQuadHit& hit) {
  const Projected a = project<KX, KY, KZ>(ray, p00), b = project<KX, KY, KZ>(ray, p10),
                  c = project<KX, KY, KZ>(ray, p01), d = project<KX, KY, KZ>(ray, p11);
  float t1, b1, c1, t2, b2, c2;
  const bool h1 = hitTriangle(a, b, d, tmin, tmax, t1, b1, c1);
  const bool h2 = hitTriangle(a, d, c, tmin, tmax, t2, b2, c2);
  if (!h1 && !h2) return false;
  const bool first = h1 && (!h2 || t1 <= t2);
  if (first) hit = {t1, std::min(1.0f, b1 + c1), c1, Vec3{}};
  else hit = {t2, b2, std::min(1.0f, b2 + c2), Vec3{}};
  if (!unitTriangleNormal(p00, first ? p10 : p11, first ? p11 : p01, hit.ng) &&
      !unitTriangleNormal(p00, first ? p11 : p10, first ? p01 : p11, hit.ng))
    hit.ng = Vec3{0, 0, 0};
  return true;
}

}  // namespace detail

// A point of a moving grid between two time samples: (1 - alpha) a + alpha b as w0 a + w1 b.
// Monotone in a and b, so blended boxes hold the blended points (DiceBuffer's motion).
inline Vec3 lerpPoint(Vec3 a, Vec3 b, float w0, float w1) { return a * w0 + b * w1; }

// The shading normal of a micro-quad: the unit bilinear blend of its corner normals at local
// (s, r) (as in MicroQuadHit); zero if they cancel. Every engine blends this way, so shading
// does not depend on which engine found the hit.
inline Vec3 blendNormals(Vec3 n00, Vec3 n10, Vec3 n01, Vec3 n11, float s, float r) {
  const Vec3 blend = (n00 * (1.0f - s) + n10 * s) * (1.0f - r) + (n01 * (1.0f - s) + n11 * s) * r;
  return detail::unitOrZero(blend);
}

// The partial derivatives of the bilinear micro-quad (p00, p10, p01, p11) at local (s, r), per
// unit of the patch parameters: d/ds and d/dr times `cellsPerUnit` (2^level, the quads per unit
// of u and of v). The bilinear partials rather than the hit triangle's edges: they vary
// continuously across the quad's diagonal, and over a quad they are the patch's own partials
// to within the dicing error. Every engine computes them this way (HitDerivatives).
// Finite for finite corners; zero along a collapsed edge (a pole).
inline void quadPartials(Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11, float s, float r, float cellsPerUnit, Vec3& dpdu,
                         Vec3& dpdv) {
  dpdu = ((p10 - p00) * (1.0f - r) + (p11 - p01) * r) * cellsPerUnit;
  dpdv = ((p01 - p00) * (1.0f - s) + (p11 - p10) * s) * cellsPerUnit;
}

// Nearest hit with t in (tmin, tmax) on the two triangles of the micro-quad; on a tie in t the
// first triangle (p00, p10, p11) wins. ng is the unit normal of the triangle hit. A zero-area
// triangle whose vertices are distinct but collinear can still be claimed: rounding in the
// sheared frame gives it a sliver of projected area, and its neighbours leave that sliver to
// it, so rejecting it would open a hole. Its ng is then the other triangle's normal, or zero
// when both are degenerate (the caller falls back to the vertex normals). Coincident vertices
// (poles) project to identical points and never claim anything.
[[gnu::always_inline]] inline bool intersectMicroQuad(const WatertightRay& ray, Vec3 p00, Vec3 p10, Vec3 p01, Vec3 p11,
                               float tmin, float tmax, MicroQuadHit& hit) {
  using detail::intersectMicroQuadOn;
  switch (ray.axes) {
    case 0: return intersectMicroQuadOn<1, 2, 0>(ray, p00, p10, p01, p11, tmin, tmax, hit);
    case 1: return intersectMicroQuadOn<2, 1, 0>(ray, p00, p10, p01, p11, tmin, tmax, hit);
    case 2: return intersectMicroQuadOn<2, 0, 1>(ray, p00, p10, p01, p11, tmin, tmax, hit);
    case 3: return intersectMicroQuadOn<0, 2, 1>(ray, p00, p10, p01, p11, tmin, tmax, hit);
    case 4: return intersectMicroQuadOn<0, 1, 2>(ray, p00, p10, p01, p11, tmin, tmax, hit);
    default: return intersectMicroQuadOn<1, 0, 2>(ray, p00, p10, p01, p11, tmin, tmax, hit);
  }
}

}  // namespace rayes
