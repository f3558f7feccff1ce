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
//
// Why it is written this way (each step measured, bench/RESULTS-dicing.md): a step tests the 4
// children of a node at once, one SSE slab test on their SoA group (DiceBuffer::nodes_), with
// intersectBox's arithmetic lane by lane so that culling and entry distances are unchanged to
// the bit; the nearest hit child is visited next without touching the stack, the others are
// pushed far first; the next level's groups are prefetched while this one is tested (at m = 8
// the tree and grid exceed L2). Tried and dropped as no faster: a branch-free SIMD sort of the
// children, visiting micro-quads straight from their parent's test instead of via the stack,
// nearest-first order for shadow rays, a sqrt-free normal check for shadow rays, skipping the
// root box test.
#include <xmmintrin.h>
#include <algorithm>
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "dicing/morton.h"
#include "dicing/patch_math.h"

namespace rayes {

namespace {

struct StackEntry {
  uint32_t node;  // Z-order index within its level
  int level;
  float tEntry;
};

// 1 + 3 per level: a step pops one node and pushes at most 3 (the 4th is visited at once).
constexpr int kStackSize = 1 + 3 * 12 + 3;

// The ray of one traversal, prepared once for 4-wide slab tests on a node group (the 4
// children of a node, SoA, see DiceBuffer::nodes_). It performs core/box.h intersectBox's
// arithmetic operation for operation on the margin-padded boxes, so every lane gives exactly
// the bits intersectBox would: near plane = (plane + signedPad - org) * invDir (x - m equals
// x + (-m) in IEEE arithmetic), far plane the same times 1 + 2*gamma(3); entry = tn > t0 ? tn :
// t0 is _mm_max_ps(tn, t0) and exit = tf < t1 ? tf : t1 is _mm_min_ps(tf, t1), NaN cases
// included. Per ray the only choice left is which of lo/hi is the near plane per axis.
struct GroupRay {
  int nearOff[3], farOff[3];  // float offsets of the near/far plane lanes within a group
  __m128 nearPad[3], farPad[3], org[3], inv[3];
  __m128 tmin, scale;

  GroupRay(const RayBoxQuery& q, float margin, float tMin) {
    for (int a = 0; a < 3; ++a) {
      const bool neg = q.sign[a] != 0;  // near plane is hi
      nearOff[a] = 8 * a + (neg ? 4 : 0);
      farOff[a] = 8 * a + (neg ? 0 : 4);
      nearPad[a] = _mm_set1_ps(neg ? margin : -margin);
      farPad[a] = _mm_set1_ps(neg ? -margin : margin);
      org[a] = _mm_set1_ps(q.org[a]);
      inv[a] = _mm_set1_ps(q.invDir[a]);
    }
    tmin = _mm_set1_ps(tMin);
    scale = _mm_set1_ps(1.0f + 2.0f * gammaBound(3));
  }

  // Bit c set: child c is crossed within [tmin, tCull]; tEntry[c] its entry distance.
  int test(const float* group, float tCull, __m128& tEntry) const {
    __m128 t0 = tmin, t1 = _mm_set1_ps(tCull);
    for (int a = 0; a < 3; ++a) {
      const __m128 n = _mm_loadu_ps(group + nearOff[a]);
      const __m128 f = _mm_loadu_ps(group + farOff[a]);
      const __m128 tn = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(n, nearPad[a]), org[a]), inv[a]);
      const __m128 tf = _mm_mul_ps(_mm_mul_ps(_mm_sub_ps(_mm_add_ps(f, farPad[a]), org[a]), inv[a]), scale);
      t0 = _mm_max_ps(tn, t0);
      t1 = _mm_min_ps(tf, t1);
    }
    tEntry = t0;
    return _mm_movemask_ps(_mm_cmple_ps(t0, t1));
  }
};

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
  const GroupRay gray(query, margin, tmin);

  const uint32_t stride = 1u << (level_ - k);
  const size_t res = size_t(resolution());
  float bestT = tmax;
  uint32_t bestQuad = UINT32_MAX;
  uint32_t bestX = 0, bestY = 0;
  MicroQuadHit best;

  StackEntry stack[kStackSize];
  int sp = 0;
  // The node being visited: its entry distance is <= bestT (tested against it when it was
  // reached, or on popping).
  uint32_t node = 0;
  int level = 0;
  float tNode, tExit;
  {
    const float* r = rootBox();
    if (!intersectBox(query, Vec3{r[0], r[1], r[2]} - pad, Vec3{r[3], r[4], r[5]} + pad, tmin, tmax, tNode,
                      tExit))
      return false;
  }
  for (;;) {
    if (level == k) {
      const uint32_t x = detail::mortonX(node), y = detail::mortonY(node);
      const Vec3* p = &positions_[size_t(y) * stride * res + size_t(x) * stride];
      const Vec3 p00 = p[0], p10 = p[stride], p01 = p[stride * res], p11 = p[stride * res + stride];
      MicroQuadHit h;
      bool accept = intersectMicroQuad(wray, p00, p10, p01, p11, tmin, tmax, h);
      if (accept) {
        float tBox = tNode;
        // At the finest level the node box *is* the corner box (same vmin/vmax), tested with
        // the same arithmetic against tCull = bestT <= tmax, so tNode is already its entry
        // distance. Coarser levels test the coarse quad's own corner box.
        if (k != level_)
          accept = intersectBox(query, vmin(vmin(p00, p10), vmin(p01, p11)) - pad,
                                vmax(vmax(p00, p10), vmax(p01, p11)) + pad, tmin, tmax, tBox, tExit);
        if (accept) {
          h.t = std::max(h.t, tBox);
          accept = h.t < tmax;
        }
      }
      if (accept && h.ng == Vec3{0, 0, 0}) {
        // Both triangles have zero area: the quad's vertex normals are the only direction left.
        h.ng = blendedNormal(&normals_[size_t(y) * stride * res + size_t(x) * stride], stride, res, h.s, h.r);
        accept = !(h.ng == Vec3{0, 0, 0});
      }
      if (accept) {
        if constexpr (AnyHit) return true;
        const uint32_t quad = (y << k) | x;
        if (h.t < bestT || (h.t == bestT && quad < bestQuad)) {
          bestT = h.t;
          bestQuad = quad;
          bestX = x;
          bestY = y;
          best = h;
          // The shading normal is blended from this quad's vertex normals once the traversal
          // ends: start loading them now.
          const Vec3* n = &normals_[size_t(y) * stride * res + size_t(x) * stride];
          _mm_prefetch(reinterpret_cast<const char*>(n), _MM_HINT_T0);
          _mm_prefetch(reinterpret_cast<const char*>(n + stride + 1) - 1, _MM_HINT_T0);
          _mm_prefetch(reinterpret_cast<const char*>(n + stride * res), _MM_HINT_T0);
          _mm_prefetch(reinterpret_cast<const char*>(n + stride * res + stride + 1) - 1, _MM_HINT_T0);
        }
      }
    } else {
      if (level + 1 < k) {
        // The 4 children's groups (384 contiguous bytes) are what the next step loads:
        // fetch them while this group is tested.
        const char* next = reinterpret_cast<const char*>(nodeGroup(level + 1, 4 * node));
        for (int line = 0; line < 384; line += 64) _mm_prefetch(next + line, _MM_HINT_T0);
      } else {
        // The children are micro-quads: fetch the 3 grid rows of their corners.
        const size_t x0 = 2 * size_t(detail::mortonX(node)) * stride, y0 = 2 * size_t(detail::mortonY(node)) * stride;
        for (size_t r = 0; r <= 2; ++r) {
          const Vec3* row = &positions_[(y0 + r * stride) * res + x0];
          _mm_prefetch(reinterpret_cast<const char*>(row), _MM_HINT_T0);
          _mm_prefetch(reinterpret_cast<const char*>(row + 2 * stride) + sizeof(Vec3) - 1, _MM_HINT_T0);
        }
      }
      __m128 te;
      int mask = gray.test(nodeGroup(level, node), bestT, te);
      if (mask != 0) {
        alignas(16) float t[4];
        _mm_store_ps(t, te);
        const uint32_t first = 4 * node;
        ++level;
        if ((mask & (mask - 1)) == 0) {  // one child: visit it, no stack
          const int c = __builtin_ctz(unsigned(mask));
          node = first + uint32_t(c);
          tNode = t[c];
          continue;
        }
        StackEntry hit[4];
        int n = 0;
        for (; mask != 0; mask &= mask - 1) {
          const int c = __builtin_ctz(unsigned(mask));
          hit[n++] = {first + uint32_t(c), level, t[c]};
        }
        if constexpr (!AnyHit) {
          // Nearest first: it is visited now, the others are pushed far first.
          for (int a = 1; a < n; ++a)
            for (int b = a; b > 0 && hit[b].tEntry < hit[b - 1].tEntry; --b) std::swap(hit[b], hit[b - 1]);
        }
        for (int c = n - 1; c > 0; --c) stack[sp++] = hit[c];
        node = hit[0].node;
        tNode = hit[0].tEntry;
        continue;
      }
    }
    // Pop the next node still entered no later than the best hit (equal stays: a tie may
    // still win on quad index).
    for (;;) {
      if (sp == 0) goto done;
      const StackEntry& e = stack[--sp];
      if (e.tEntry > bestT) continue;
      node = e.node;
      level = e.level;
      tNode = e.tEntry;
      break;
    }
  }
done:
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
