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
// the tree *are* the coarser dicings (docs/design.md, invariant 2).
//
// Why the boxes get a margin: the watertight test decides on vertices rounded in the ray's
// sheared frame, i.e. on triangles moved by a few ulps of their distance from the ray origin.
// The margin gamma(16) * (farthest patch-bound corner from the origin) covers that, so a
// triangle's claim is never lost to its box; 2^-22 * (largest patch coordinate), at least two
// ulps of any box coordinate, keeps `lo - margin` from rounding back to `lo` far from the
// origin. It is per ray and per patch, never per box, so containment (and hence the exactness
// above) is kept.
//
// Why it is written this way (each step measured, bench/history/RESULTS-dicing.md): a step tests
// the 4 children of a node at once, one SSE slab test on their SoA group (DiceBuffer::nodes_), with
// intersectBox's arithmetic lane by lane so that culling and entry distances are unchanged to the
// bit; the nearest hit child is visited next without touching the stack, the others are pushed far
// first; the next level's groups are prefetched while this one is tested (at m = 8 the tree and
// grid exceed L2). Tried and dropped as no faster: a branch-free SIMD sort of the children,
// visiting micro-quads straight from their parent's test instead of via the stack, nearest-first
// order for shadow rays, a sqrt-free normal check for shadow rays, skipping the root box test.
// Instruction counts (callgrind, bench/history/2026-11.md, "Where the bottom level's instructions
// go"): group offsets from a table and (x, y) carried with each node rather than decoded from
// its Morton index, the micro-quad projection on template axes: 5,305 -> 4,390 per ray on
// bench_dicing_embree's grid; the thin regions' walk is skipped whole when the ray misses the
// border's bounds. A static dicing's micro-quad children pass quadsMayHit4 (their edge signs,
// 4 quads in one SSE pass) before they reach the stack: 4,387 -> 4,206 per ray when the node has
// 2 or more such children (gating single children too: 4,280; testing the 4 quads from the
// parent instead of via the stack: 4,797 -- the stack's nearest-first pops skip the siblings
// behind a hit); time unchanged within the noise (bench/history/2026-11.md, "The bottom level's
// second session").
#include <xmmintrin.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include "core/box4.h"
#include "core/next_float.h"
#include "dicing/dice_buffer.h"
#include "dicing/micro_quad.h"
#include "dicing/micro_quad4.h"
#include "dicing/morton.h"
#include "geometry/patch_math.h"

namespace rayes {

namespace {

struct StackEntry {
  uint32_t node;  // Z-order index within its level
  uint32_t xy;    // its (x, y) on its level as (y << 16) | x, carried down rather than decoded
                  // from node (detail::mortonX/Y were 5 % of a traversal's instructions)
  int level;
  float tEntry;
};

// Child c (Z-order) of the node at xy: (2x + (c & 1), 2y + (c >> 1)). x, y < 2^12, so shifting
// the packed pair moves each half alone.
constexpr uint32_t kChildXY[4] = {0, 1, 1u << 16, (1u << 16) | 1};
constexpr uint32_t childXY(uint32_t xy, int c) { return (xy << 1) | kChildXY[c]; }


// 1 + 3 per level: a step pops one node and pushes at most 3 (the 4th is visited at once).
constexpr int kStackSize = 1 + 3 * 12 + 3;

// The ray of one traversal, prepared once for 4-wide slab tests on a node group (the 4
// children of a node, SoA, see DiceBuffer::nodes_): core/box4.h's test on the margin-padded
// boxes, so every lane gives exactly the bits intersectBox gives on `lo - margin, hi + margin`
// (x - m equals x + (-m) in IEEE arithmetic). Per ray the only choice left is which of lo/hi is
// the near plane per axis.
struct GroupRay {
  int nearOff[3], farOff[3];  // float offsets of the near/far plane lanes within a group
  __m128 nearPad[3], farPad[3];
  RayBox4Query ray;
  __m128 tmin;

  GroupRay(const RayBoxQuery& q, float margin, float tMin) : ray(q) {
    for (int a = 0; a < 3; ++a) {
      const bool neg = q.sign[a] != 0;  // near plane is hi
      nearOff[a] = 8 * a + (neg ? 4 : 0);
      farOff[a] = 8 * a + (neg ? 0 : 4);
      nearPad[a] = _mm_set1_ps(neg ? margin : -margin);
      farPad[a] = _mm_set1_ps(neg ? -margin : margin);
    }
    tmin = _mm_set1_ps(tMin);
  }

  // Bit c set: child c is crossed within [tmin, tCull]; tEntry[c] its entry distance.
  int test(const float* group, float tCull, __m128& tEntry) const {
    __m128 n[3], f[3];
    for (int a = 0; a < 3; ++a) {
      n[a] = _mm_loadu_ps(group + nearOff[a]);
      f[a] = _mm_loadu_ps(group + farOff[a]);
    }
    return slabs(n, f, tCull, tEntry);
  }

  // The same test on the group interpolated between two time samples, w0 * a + w1 * b lane by
  // lane (monotone in a and b: the blended box contains the blended points).
  int testLerp(const float* a, const float* b, __m128 w0, __m128 w1, float tCull, __m128& tEntry) const {
    __m128 n[3], f[3];
    for (int k = 0; k < 3; ++k) {
      n[k] = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(a + nearOff[k]), w0), _mm_mul_ps(_mm_loadu_ps(b + nearOff[k]), w1));
      f[k] = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(a + farOff[k]), w0), _mm_mul_ps(_mm_loadu_ps(b + farOff[k]), w1));
    }
    return slabs(n, f, tCull, tEntry);
  }

 private:
  int slabs(const __m128 n[3], const __m128 f[3], float tCull, __m128& tEntry) const {
    __m128 nearPlane[3], farPlane[3], tExit;
    for (int a = 0; a < 3; ++a) {
      nearPlane[a] = _mm_add_ps(n[a], nearPad[a]);
      farPlane[a] = _mm_add_ps(f[a], farPad[a]);
    }
    return int(intersectBox4(ray, nearPlane, farPlane, tmin, _mm_set1_ps(tCull), tEntry, tExit));
  }
};


// The unit normal at local (s, r) of the micro-quad whose first corner is vertex i00 (corners
// `stride` apart, rows `res` apart): blendNormals of its corner normals -- on a moving dicing
// each corner's normal first blended between the two samples with the time weights, as its
// position is. Zero if they cancel.
template <bool Moving>
Vec3 quadNormal(const Vec3* normalsA, const Vec3* normalsB, size_t i00, uint32_t stride, size_t res,
                float w0, float w1, float s, float r) {
  const size_t corner[4] = {i00, i00 + stride, i00 + stride * res, i00 + stride * res + stride};
  Vec3 n[4];
  for (int c = 0; c < 4; ++c) {
    if constexpr (Moving) n[c] = lerpPoint(normalsA[corner[c]], normalsB[corner[c]], w0, w1);
    else n[c] = normalsA[corner[c]];
  }
  return blendNormals(n[0], n[1], n[2], n[3], s, r);
}

// The ray's parameter interval [c0, c1] inside the infinite cylinder of radius r about the
// line through a and b, in double (false: it misses). A degenerate chord (a == b) bounds
// nothing: the whole line. A ray parallel to the axis is inside everywhere or nowhere.
bool rayCylinder(Vec3 org, Vec3 dir, Vec3 a, Vec3 b, double r, double& c0, double& c1) {
  constexpr double kInfD = std::numeric_limits<double>::infinity();
  const double ax[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double len = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  if (!(len > 0) || !std::isfinite(len)) {
    c0 = -kInfD;
    c1 = kInfD;
    return true;
  }
  const double u[3] = {ax[0] / len, ax[1] / len, ax[2] / len};
  const double w[3] = {double(org.x) - a.x, double(org.y) - a.y, double(org.z) - a.z};
  const double d[3] = {dir.x, dir.y, dir.z};
  const double wu = w[0] * u[0] + w[1] * u[1] + w[2] * u[2], du = d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
  double A = 0, B = 0, C = -r * r, dd = 0;
  for (int i = 0; i < 3; ++i) {
    const double wp = w[i] - wu * u[i], dp = d[i] - du * u[i];
    A += dp * dp;
    B += wp * dp;
    C += wp * wp;
    dd += d[i] * d[i];
  }
  if (!(A > 1e-24 * dd)) {  // along the axis
    if (!(C <= 0)) return false;
    c0 = -kInfD;
    c1 = kInfD;
    return true;
  }
  const double disc = B * B - A * C;
  if (!(disc >= 0)) return false;
  const double sq = std::sqrt(disc);
  c0 = (-B - sq) / A;
  c1 = (-B + sq) / A;
  return true;
}

struct BorderEntry {
  uint32_t j;
  int level;
  float tEntry;
};

}  // namespace

// The best hit so far of one traversal: micro-quad (x, y) at the ray's level, local (s, r).
struct DiceBuffer::Best {
  float t;
  uint32_t quad = UINT32_MAX;
  uint32_t x = 0, y = 0;
  float s = 0, r = 0;
  Vec3 ng;
  bool border = false;
};

template <bool AnyHit, bool Moving>
bool DiceBuffer::traverse(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, float alpha,
                          const BorderRegions& regions, GridHit* out) const {
  static_assert([] {
    for (int i = 0; i < 14; ++i)
      if (kLevelGroups[i] != detail::levelOffset(i)) return false;
    return true;
  }());
  if (!(tmin < tmax)) return false;
  WatertightRay wray;
  if (!makeWatertightRay(org, dir, wray)) return false;
  const int k = std::clamp(rayLevel, 0, level_);
  const RayBoxQuery query(org, dir);
  const float farthest = maxComponent(vmax(vabs(patchBounds_.lo - org), vabs(patchBounds_.hi - org)));
  const float magnitude = maxComponent(vmax(vabs(patchBounds_.lo), vabs(patchBounds_.hi)));
  const float watertightError = gammaBound(16) * farthest;
  const float margin = watertightError + 0x1p-22f * magnitude;
  if (!std::isfinite(margin)) return false;
  const Vec3 pad{margin, margin, margin};
  const GroupRay gray(query, margin, tmin);
  // Motion: the weights of the two samples (unused by the static instantiation).
  const float w1 = Moving ? std::clamp(alpha, 0.0f, 1.0f) : 0.0f;
  const float w0 = 1.0f - w1;
  [[maybe_unused]] const __m128 w0v = _mm_set1_ps(w0), w1v = _mm_set1_ps(w1);
  // Plain pointers, hoisted: the hot loop reads through registers, not through the vectors.
  const Vec3* const positions_ = a_.positions.data();
  const Vec3* const normals_ = a_.normals.data();
  const float* const nodesA = a_.nodes.data();
  [[maybe_unused]] const Vec3* const posB = b_.positions.data();
  const Vec3* const normalsB = b_.normals.data();
  [[maybe_unused]] const float* const nodesB = b_.nodes.data();

  const uint32_t stride = 1u << (level_ - k);
  const size_t res = size_t(resolution());
  float bestT = tmax;
  uint32_t bestQuad = UINT32_MAX;
  uint32_t bestX = 0, bestY = 0;
  MicroQuadHit bestQuadHit;

  StackEntry stack[kStackSize];
  int sp = 0;
  // The node being visited: its entry distance is <= bestT (tested against it when it was
  // reached, or on popping).
  uint32_t node = 0, xy = 0;
  int level = 0;
  float tNode, tExit;
  {
    const float* r = nodesA + groupOffset(maxLevel_, 0);
    Vec3 lo{r[0], r[1], r[2]}, hi{r[3], r[4], r[5]};
    if constexpr (Moving) {
      const float* rb = nodesB + groupOffset(maxLevel_, 0);
      lo = lerpPoint(lo, Vec3{rb[0], rb[1], rb[2]}, w0, w1);
      hi = lerpPoint(hi, Vec3{rb[3], rb[4], rb[5]}, w0, w1);
    }
    if (!intersectBox(query, lo - pad, hi + pad, tmin, tmax, tNode, tExit)) goto borders;
  }
  for (;;) {
    if (level == k) {
      const uint32_t x = xy & 0xffffu, y = xy >> 16;
      const size_t i00 = size_t(y) * stride * res + size_t(x) * stride;
      const Vec3* p = &positions_[i00];
      Vec3 p00 = p[0], p10 = p[stride], p01 = p[stride * res], p11 = p[stride * res + stride];
      if constexpr (Moving) {
        const Vec3* q = &posB[i00];
        p00 = lerpPoint(p00, q[0], w0, w1);
        p10 = lerpPoint(p10, q[stride], w0, w1);
        p01 = lerpPoint(p01, q[stride * res], w0, w1);
        p11 = lerpPoint(p11, q[stride * res + stride], w0, w1);
      }
      MicroQuadHit h;
      bool accept = intersectMicroQuad(wray, p00, p10, p01, p11, tmin, tmax, h);
      if (accept) {
        float tBox = tNode;
        // At the finest level of a static dicing the node box *is* the corner box (same
        // vmin/vmax), tested with the same arithmetic against tCull = bestT <= tmax, so tNode
        // is already its entry distance. Coarser levels, and interpolated boxes, test the
        // quad's own corner box.
        if (Moving || k != level_)
          accept = intersectBox(query, vmin(vmin(p00, p10), vmin(p01, p11)) - pad,
                                vmax(vmax(p00, p10), vmax(p01, p11)) + pad, tmin, tmax, tBox, tExit);
        if (accept) {
          h.t = std::max(h.t, tBox);
          accept = h.t < tmax;
        }
      }
      if (accept && h.ng == Vec3{0, 0, 0}) {
        // Both triangles have zero area: the quad's vertex normals are the only direction left.
        h.ng = quadNormal<Moving>(normals_, normalsB, i00, stride, res, w0, w1, h.s, h.r);
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
          bestQuadHit = h;
          // The shading normal is blended from this quad's vertex normals once the traversal
          // ends: start loading them now.
          const Vec3* n = &normals_[i00];
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
        const char* next = reinterpret_cast<const char*>(nodesA + groupOffset(level + 1, 4 * node));
        for (int line = 0; line < 384; line += 64) _mm_prefetch(next + line, _MM_HINT_T0);
        if constexpr (Moving) {
          const char* nextB = reinterpret_cast<const char*>(nodesB + groupOffset(level + 1, 4 * node));
          for (int line = 0; line < 384; line += 64) _mm_prefetch(nextB + line, _MM_HINT_T0);
        }
      } else {
        // The children are micro-quads: fetch the 3 grid rows of their corners.
        const size_t x0 = 2 * size_t(xy & 0xffffu) * stride, y0 = 2 * size_t(xy >> 16) * stride;
        for (size_t r = 0; r <= 2; ++r) {
          const Vec3* row = &positions_[(y0 + r * stride) * res + x0];
          _mm_prefetch(reinterpret_cast<const char*>(row), _MM_HINT_T0);
          _mm_prefetch(reinterpret_cast<const char*>(row + 2 * stride) + sizeof(Vec3) - 1, _MM_HINT_T0);
          if constexpr (Moving) {
            const Vec3* rowB = &posB[(y0 + r * stride) * res + x0];
            _mm_prefetch(reinterpret_cast<const char*>(rowB), _MM_HINT_T0);
            _mm_prefetch(reinterpret_cast<const char*>(rowB + 2 * stride) + sizeof(Vec3) - 1, _MM_HINT_T0);
          }
        }
      }
      __m128 te;
      int mask;
      if constexpr (Moving)
        mask = gray.testLerp(nodesA + groupOffset(level, node), nodesB + groupOffset(level, node), w0v, w1v, bestT, te);
      else
        mask = gray.test(nodesA + groupOffset(level, node), bestT, te);
      if constexpr (!Moving) {
        // Children that are micro-quads reach the stack only if their triangles' edge signs
        // allow a hit (quadsMayHit4 clears exactly the quads intersectMicroQuad rejects on
        // those alone), so the others cost no push, pop or scalar test.
        if ((mask & (mask - 1)) != 0 && level + 1 == k) {
          const size_t x0 = 2 * size_t(xy & 0xffffu) * stride, y0 = 2 * size_t(xy >> 16) * stride;
          mask &= quadsMayHit4(wray, &positions_[y0 * res + x0], stride, stride * res);
        }
      }
      if (mask != 0) {
        alignas(16) float t[4];
        _mm_store_ps(t, te);
        const uint32_t first = 4 * node;
        ++level;
        if ((mask & (mask - 1)) == 0) {  // one child: visit it, no stack
          const int c = __builtin_ctz(unsigned(mask));
          node = first + uint32_t(c);
          xy = childXY(xy, c);
          tNode = t[c];
          continue;
        }
        StackEntry hit[4];
        int n = 0;
        for (; mask != 0; mask &= mask - 1) {
          const int c = __builtin_ctz(unsigned(mask));
          hit[n++] = {first + uint32_t(c), childXY(xy, c), level, t[c]};
        }
        if constexpr (!AnyHit) {
          // Nearest first: it is visited now, the others are pushed far first.
          for (int a = 1; a < n; ++a)
            for (int b = a; b > 0 && hit[b].tEntry < hit[b - 1].tEntry; --b) std::swap(hit[b], hit[b - 1]);
        }
        for (int c = n - 1; c > 0; --c) stack[sp++] = hit[c];
        node = hit[0].node;
        xy = hit[0].xy;
        tNode = hit[0].tEntry;
        continue;
      }
    }
    // Pop the next node still entered no later than the best hit (equal stays: a tie may
    // still win on quad index).
    for (;;) {
      if (sp == 0) goto borders;
      const StackEntry& e = stack[--sp];
      if (e.tEntry > bestT) continue;
      node = e.node;
      xy = e.xy;
      level = e.level;
      tNode = e.tEntry;
      break;
    }
  }
borders:
  Best best;
  best.t = bestT;
  best.quad = bestQuad;
  best.x = bestX;
  best.y = bestY;
  best.s = bestQuadHit.s;
  best.r = bestQuadHit.r;
  best.ng = bestQuadHit.ng;
  if (regions.mask && borders_) {
    if (traverseBorders<AnyHit, Moving>(query, dir, pad, watertightError, tmin, tmax, k, w0, w1, regions, best) &&
        AnyHit)
      return true;
  }
  if (best.quad == UINT32_MAX) return false;

  // On the parent's grid for a sub-leaf (subDepth_ > 0): its cell and level there.
  const int kp = k + subDepth_;
  const uint32_t cx = (subX_ << k) + best.x, cy = (subY_ << k) + best.y;
  const float inv = 1.0f / float(1u << kp);  // a power of two: the scaling below is exact
  GridHit& g = *out;
  g.t = best.t;
  g.u = (float(cx) + best.s) * inv;
  g.v = (float(cy) + best.r) * inv;
  g.quad = subDepth_ ? (cy << kp) | cx : best.quad;
  g.ng = best.ng;
  g.border = best.border;
  const size_t i00 = size_t(best.y) * stride * res + size_t(best.x) * stride;
  const Vec3 ns = quadNormal<Moving>(normals_, normalsB, i00, stride, res, w0, w1, best.s, best.r);
  g.ns = ns == Vec3{0, 0, 0} ? best.ng : ns;
  {
    // The hit quad's corners at the ray's time (as the micro-quad test saw them).
    const size_t c[4] = {i00, i00 + stride, i00 + stride * res, i00 + stride * res + stride};
    Vec3 p[4];
    for (int j = 0; j < 4; ++j) {
      if constexpr (Moving) p[j] = lerpPoint(positions_[c[j]], posB[c[j]], w0, w1);
      else p[j] = positions_[c[j]];
    }
    quadPartials(p[0], p[1], p[2], p[3], std::clamp(best.s, 0.0f, 1.0f), std::clamp(best.r, 0.0f, 1.0f),
                 float(1u << kp), g.dpdu, g.dpdv);
  }
  return true;
}

// The border regions at the ray's level k (see DiceBuffer::intersect): per border, a
// depth-first walk of the binary tree of its segments, pruned by the slab test on each
// segment's box against the best hit so far (inclusive, as the quad-tree walk). A static
// dicing's boxes are its segments' own (regionBox, computed on first use): each holds the true
// curve and every grid vertex of its segment, so a region part that closes a slit is never
// pruned, and the walk depends on (ray, k) alone. A moving dicing's are its tree's, blended.
// Returns true when it improved `best` (for AnyHit: found any hit).
template <bool AnyHit, bool Moving>
bool DiceBuffer::traverseBorders(const RayBoxQuery& q, Vec3 dir, const Vec3& pad, float watertightError, float tmin,
                                 float tmax, int k, float w0, float w1, const BorderRegions& regions,
                                 Best& best) const {
  const uint32_t stride = 1u << (level_ - k);
  const size_t res = size_t(resolution());
  const uint32_t last = (1u << k) - 1;
  const Vec3* const positions_ = a_.positions.data();
  const Vec3* const normals_ = a_.normals.data();
  bool found = false;
  auto box = [&](int e, int lv, uint32_t j, Vec3& lo, Vec3& hi) {
    if (!Moving && !moving_) {
      const Box3 r = regionBox(e, lv, j);
      lo = r.lo;
      hi = r.hi;
      return;
    }
    const size_t o = borderOffset(e, lv, j);
    const float* a = a_.borders.data() + o;
    lo = Vec3{a[0], a[1], a[2]};
    hi = Vec3{a[3], a[4], a[5]};
    if constexpr (Moving) {
      const float* b = b_.borders.data() + o;
      lo = lerpPoint(lo, Vec3{b[0], b[1], b[2]}, w0, w1);
      hi = lerpPoint(hi, Vec3{b[3], b[4], b[5]}, w0, w1);
    }
  };
  auto vertex = [&](size_t i) {
    if constexpr (Moving) return lerpPoint(positions_[i], b_.positions[i], w0, w1);
    else return positions_[i];
  };
  // One segment's region at level k, entered at t0 and left at t1 within its box: thin >= 0
  // is a thin region's radius, else the radius that holds the curve. Returns true when an
  // any-hit query is done.
  auto region = [&](int e, uint32_t j, float t0, float t1, double thin) -> bool {
    // The border micro-quad and its triangle that holds the segment (micro_quad.h's split).
    uint32_t x, y;
    switch (e) {
      case 0: x = j; y = 0; break;
      case 1: x = last; y = j; break;
      case 2: x = j; y = last; break;
      default: x = 0; y = j; break;
    }
    const size_t i00 = size_t(y) * stride * res + size_t(x) * stride;
    const Vec3 p00 = vertex(i00), p10 = vertex(i00 + stride), p01 = vertex(i00 + stride * res),
               p11 = vertex(i00 + stride * res + stride);
    const bool first = e == 0 || e == 1;  // (p00, p10, p11) holds the v=0 and u=1 segments
    Vec3 ng;
    if (!detail::unitTriangleNormal(p00, first ? p10 : p11, first ? p11 : p01, ng) &&
        !detail::unitTriangleNormal(p00, first ? p11 : p10, first ? p01 : p11, ng))
      ng = Vec3{0, 0, 0};
    const Vec3 a = e == 0 || e == 3 ? p00 : e == 1 ? p10 : p01;
    const Vec3 b = e == 0 ? p10 : e == 3 ? p01 : p11;
    // The region is the box cut down to the cylinder about the chord's line that holds the
    // true curve (a box alone, about a diagonal chord, would reach far off the surface).
    // Its entry must come after the ray's start: a ray starting inside is not stopped.
    {
      double c0, c1;
      double radius;
      if (thin >= 0) {
        radius = thin;
      } else if constexpr (Moving) {
        radius = borderRadius(e, k, j, a, b, 3, true, w0, w1);
      } else {
        // The radius is the smaller of two bounds, from 8 pieces and from the finer pieces of
        // radiusSplit(k) (<= 64): the first is cheap, and a ray that misses its cylinder, or
        // enters it after the best hit, misses the region whatever the second (shrinking the
        // cylinder only delays the entry and advances the exit), so most rays near a coarse
        // segment never need the second. The region is the same function of (k, j) either way.
        radius = cachedRadius(e, k, j, a, b, true);
        if (radiusSplit(k) > 3) {
          if (!rayCylinder(q.org, dir, a, b, radius + double(watertightError), c0, c1)) return false;
          const float entry = std::max(t0, floatBelow(c0));
          if (!(entry <= std::min(t1, floatAbove(c1))) || entry > best.t) return false;
          radius = std::min(radius, cachedRadius(e, k, j, a, b, false));
        }
      }
      // The cylinder is tested in double: only the watertight test's rounding is added to
      // the radius, not the ulps that keep float box bounds moving (a region at a silhouette
      // would widen it by them).
      if (!rayCylinder(q.org, dir, a, b, radius + double(watertightError), c0, c1))
        return false;
      t0 = std::max(t0, floatBelow(c0));
      t1 = std::min(t1, floatAbove(c1));
      if (!(t0 <= t1) || !(t0 > tmin) || t0 > best.t) return false;
    }
    // The crossing of the triangle's plane, kept inside the box.
    float t = t0;
    if (!(ng == Vec3{0, 0, 0})) {
      const float tp = dot(a - q.org, ng) / dot(dir, ng);
      if (std::isfinite(tp)) t = std::clamp(tp, t0, std::max(t0, t1));
    }
    if (!(t < tmax)) return false;
    const Vec3 hitPoint = q.org + dir * t;
    const Vec3 chord = b - a;
    const float len2 = dot(chord, chord);
    float lambda = len2 > 0 ? dot(hitPoint - a, chord) / len2 : 0.0f;
    lambda = std::isfinite(lambda) ? std::clamp(lambda, 0.0f, 1.0f) : 0.0f;
    const float s = e == 3 ? 0.0f : e == 1 ? 1.0f : lambda;
    const float r = e == 0 ? 0.0f : e == 2 ? 1.0f : lambda;
    if (ng == Vec3{0, 0, 0}) {
      ng = quadNormal<Moving>(normals_, b_.normals.data(), i00, stride, res, w0, w1, s, r);
      if (ng == Vec3{0, 0, 0}) return false;
    }
    if constexpr (AnyHit) return true;
    const uint32_t quad = (y << k) | x;
    if (t < best.t || (t == best.t && quad < best.quad)) {
      best.t = t;
      best.quad = quad;
      best.x = x;
      best.y = y;
      best.s = s;
      best.r = r;
      best.ng = ng;
      best.border = true;
      found = true;
    }
    return false;
  };
  for (int e = 0; e < 4; ++e) {
    if (!(regions.mask & (1u << e))) continue;
    if (regions.thin & (1u << e)) {
      // A thin region: every segment's chord at level k, in a box of its ends grown by the
      // radius (the slit lies within the radius of the chord); linear in 2^k, so only for
      // k <= BottomQuery::kMaxThinLevel, which the SortedEngine keeps to.
      const double radius = regions.thinRadius[e];
      const float grow = float(radius) * (1.0f + 1e-6f);
      const Vec3 g{grow, grow, grow};
      if (!moving_ && k <= BottomQuery::kMaxThinLevel) {
        // All of the border's segment boxes at once (thinBounds_): most rays cross none, and
        // the walk below was a third of the bottom level's instructions on teapot-field
        // (bench/history/2026-11.md, "Where the bottom level's instructions go").
        const Box3& all = thinBounds_[e][k];
        float t0, t1;
        if (!intersectBox(q, all.lo - g - pad, all.hi + g + pad, tmin, tmax, t0, t1) || t0 > best.t) continue;
      }
      size_t v0, v1;
      chordEnds(e, k, 0, level_, v0, v1);
      const size_t step = v1 - v0;  // segment j + 1 starts where j ends
      for (uint32_t j = 0; j <= last; ++j, v0 = v1, v1 += step) {
        const Vec3 a = vertex(v0), b = vertex(v1);
        float t0, t1;
        if (!intersectBox(q, vmin(a, b) - g - pad, vmax(a, b) + g + pad, tmin, tmax, t0, t1) || t0 > best.t) continue;
        if (region(e, j, t0, t1, radius) && AnyHit) return true;
      }
      continue;
    }
    BorderEntry stack[2 * 13];
    int sp = 0;
    {
      // The test below passes only for an entry before both tmax and best.t.
      if (!Moving && !mayEnterRegionBox(e, 0, 0, q, pad, tmin, std::min(tmax, best.t))) continue;
      Vec3 lo, hi;
      box(e, 0, 0, lo, hi);
      float t0, t1;
      if (!intersectBox(q, lo - pad, hi + pad, tmin, tmax, t0, t1) || t0 > best.t) continue;
      stack[sp++] = {0, 0, t0};
    }
    while (sp > 0) {
      const BorderEntry n = stack[--sp];
      if (n.tEntry > best.t) continue;
      if (n.level < k) {
        BorderEntry c[2];
        int nc = 0;
        for (uint32_t d = 0; d < 2; ++d) {
          if (!Moving && !mayEnterRegionBox(e, n.level + 1, 2 * n.j + d, q, pad, tmin, AnyHit ? tmax : best.t))
            continue;
          Vec3 lo, hi;
          box(e, n.level + 1, 2 * n.j + d, lo, hi);
          float t0, t1;
          if (intersectBox(q, lo - pad, hi + pad, tmin, AnyHit ? tmax : best.t, t0, t1))
            c[nc++] = {2 * n.j + d, n.level + 1, t0};
        }
        if (nc == 2 && c[1].tEntry < c[0].tEntry) std::swap(c[0], c[1]);
        for (int i = nc - 1; i >= 0; --i) stack[sp++] = c[i];
        continue;
      }
      // A border box at the ray's level, with its true exit (known: the walk tested it above).
      Vec3 lo, hi;
      box(e, k, n.j, lo, hi);
      float t0, t1;
      if (!intersectBox(q, lo - pad, hi + pad, tmin, tmax, t0, t1) || t0 > best.t) continue;
      if (region(e, n.j, t0, t1, -1.0) && AnyHit) return true;
    }
  }
  return found;
}

DiceBuffer::BorderRegions DiceBuffer::regionsOf(const BottomQuery& q, bool moving) {
  DiceBuffer::BorderRegions r;
  if (!q.closeBorders) return r;
  r.mask = ~unsigned(q.skipBorders) & 0xfu;
  if (!moving) r.thin = unsigned(q.thinBorders) & r.mask;
  r.thinRadius = q.thinRadius;
  return r;
}

bool DiceBuffer::intersect(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, GridHit& hit,
                           BottomQuery query) const {
  if (moving_ && query.alpha != 0.0f)
    return traverse<false, true>(org, dir, tmin, tmax, rayLevel, query.alpha, regionsOf(query, true), &hit);
  return traverse<false, false>(org, dir, tmin, tmax, rayLevel, 0.0f, regionsOf(query, moving_), &hit);
}

bool DiceBuffer::occluded(Vec3 org, Vec3 dir, float tmin, float tmax, int rayLevel, BottomQuery query) const {
  if (moving_ && query.alpha != 0.0f)
    return traverse<true, true>(org, dir, tmin, tmax, rayLevel, query.alpha, regionsOf(query, true), nullptr);
  return traverse<true, false>(org, dir, tmin, tmax, rayLevel, 0.0f, regionsOf(query, moving_), nullptr);
}

}  // namespace rayes
