// Single-ray traversal of the implicit quad-tree, down to the ray's own level of detail.
//
// Why the result is exact and order independent: a micro-quad at level k is accepted by a pure
// function of the ray and its 4 corner vertices -- the watertight triangle test, plus the same
// conservative slab test the traversal uses, on the box of the 4 corners -- and its hit
// distance is raised to at least that box's entry distance. Every tree box containing the quad
// contains that corner box, and the slab test is monotone under containment, so a box is culled
// (missed, or entered after the best t) only if every quad inside it would be rejected or would
// lose. The hit is therefore the minimum of (t, quad index) over all quads of level k, whatever
// the traversal order and whichever finer level the grid was diced at: the coarser levels of
// the tree *are* the coarser dicings (DESIGN invariant 2).
//
// Why the boxes get a margin: the watertight test decides on vertices rounded in the ray's
// sheared frame, i.e. on triangles moved by a few ulps of their distance from the ray origin.
// The margin gamma(16) * (farthest patch-bound corner from the origin) covers that, so a
// triangle's claim is never lost to its box; 2^-22 * (largest patch coordinate), at least two
// ulps of any box coordinate, keeps `lo - margin` from rounding back to `lo` far from the
// origin. It is per ray and per patch, never per box, so containment (and hence the exactness
// above) is kept.
#include <algorithm>
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "dicing/morton.h"
#include "dicing/patch_math.h"

namespace rayes {

using detail::levelOffset;

namespace {

struct StackEntry {
  uint32_t node;  // Z-order index within its level
  int level;
  float tEntry;
};

// 1 + 3 per level: a step pops one node and pushes at most 4.
constexpr int kStackSize = 1 + 3 * 12 + 3;

// Unit bilinear blend of a quad's corner normals at local (s, r); zero if they cancel.
Vec3 blendedNormal(const Vec3* n00, uint32_t stride, size_t res, float s, float r) {
  const Vec3 blend = (n00[0] * (1.0f - s) + n00[stride] * s) * (1.0f - r) +
                     (n00[stride * res] * (1.0f - s) + n00[stride * res + stride] * s) * r;
  return detail::unitOrZero(blend);
}

}  // namespace

template <bool AnyHit>
bool DiceBuffer::traverse(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel,
                          GridHit* out) const {
  if (!(tmin < tmax)) return false;
  WatertightRay wray;
  if (!makeWatertightRay(org, dir, wray)) return false;
  const int k = std::clamp(rayLevel, 0, level_);
  const RayBoxQuery query(org, dir);
  const float farthest = maxComponent(vmax(vabs(patchBounds_.lo - org), vabs(patchBounds_.hi - org)));
  const float magnitude = maxComponent(vmax(vabs(patchBounds_.lo), vabs(patchBounds_.hi)));
  const float margin = gammaBound(16) * farthest + 0x1p-22f * magnitude;
  if (!std::isfinite(margin)) return false;
  const Vec3 pad{margin, margin, margin};
  auto hitsBox = [&](Vec3 lo, Vec3 hi, float tCull, float& tEntry) {
    float tExit;
    return intersectBox(query, lo - pad, hi + pad, tmin, tCull, tEntry, tExit);
  };

  const uint32_t stride = 1u << (level_ - k);
  const size_t res = size_t(resolution());
  float bestT = tmax;
  uint32_t bestQuad = UINT32_MAX;
  uint32_t bestX = 0, bestY = 0;
  MicroQuadHit best;

  StackEntry stack[kStackSize];
  int sp = 0;
  float tEntry;
  if (!hitsBox(nodes_[0].lo, nodes_[0].hi, tmax, tEntry)) return false;
  stack[sp++] = {0, 0, tEntry};
  while (sp > 0) {
    const StackEntry e = stack[--sp];
    if (e.tEntry > bestT) continue;  // equal stays: a tie may still win on quad index
    if (e.level == k) {
      const uint32_t x = detail::mortonX(e.node), y = detail::mortonY(e.node);
      const Vec3* p = &positions_[size_t(y) * stride * res + size_t(x) * stride];
      const Vec3 p00 = p[0], p10 = p[stride], p01 = p[stride * res], p11 = p[stride * res + stride];
      MicroQuadHit h;
      if (!intersectMicroQuad(wray, p00, p10, p01, p11, tmin, tmax, h)) continue;
      float tBox;
      if (!hitsBox(vmin(vmin(p00, p10), vmin(p01, p11)), vmax(vmax(p00, p10), vmax(p01, p11)),
                   tmax, tBox))
        continue;
      h.t = std::max(h.t, tBox);
      if (!(h.t < tmax)) continue;
      if (h.ng == Vec3{0, 0, 0}) {
        // Both triangles have zero area: the quad's vertex normals are the only direction left.
        h.ng = blendedNormal(&normals_[size_t(y) * stride * res + size_t(x) * stride], stride, res, h.s, h.r);
        if (h.ng == Vec3{0, 0, 0}) continue;
      }
      if constexpr (AnyHit) return true;
      const uint32_t quad = (y << k) | x;
      if (h.t < bestT || (h.t == bestT && quad < bestQuad)) {
        bestT = h.t;
        bestQuad = quad;
        bestX = x;
        bestY = y;
        best = h;
      }
      continue;
    }
    const Box3* children = &nodes_[levelOffset(e.level + 1) + 4 * size_t(e.node)];
    StackEntry hit[4];
    int n = 0;
    for (uint32_t c = 0; c < 4; ++c) {
      if (hitsBox(children[c].lo, children[c].hi, bestT, tEntry))
        hit[n++] = {4 * e.node + c, e.level + 1, tEntry};
    }
    if constexpr (!AnyHit) {
      // Far first onto the stack, so the nearest child is popped next.
      for (int a = 1; a < n; ++a)
        for (int b = a; b > 0 && hit[b].tEntry > hit[b - 1].tEntry; --b) std::swap(hit[b], hit[b - 1]);
    }
    for (int c = 0; c < n; ++c) stack[sp++] = hit[c];
  }
  if (bestQuad == UINT32_MAX) return false;

  const float inv = 1.0f / float(1u << k);  // a power of two: the scaling below is exact
  GridHit& g = *out;
  g.t = best.t;
  g.u = (float(bestX) + best.s) * inv;
  g.v = (float(bestY) + best.r) * inv;
  g.quad = bestQuad;
  g.ng = best.ng;
  const Vec3 ns = blendedNormal(&normals_[size_t(bestY) * stride * res + size_t(bestX) * stride],
                                stride, res, best.s, best.r);
  g.ns = ns == Vec3{0, 0, 0} ? best.ng : ns;
  return true;
}

bool DiceBuffer::intersect(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel,
                           GridHit& hit) const {
  return traverse<false>(org, dir, tmin, tmax, rayLevel, &hit);
}

bool DiceBuffer::occluded(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel) const {
  return traverse<true>(org, dir, tmin, tmax, rayLevel, nullptr);
}

}  // namespace rayes
