// Axis-aligned boxes and the conservative ray/box slab test shared by both BVH levels.
// The slab test follows Ize, "Robust BVH Ray Traversal" (JCGT 2013): with exact reciprocal
// directions and tmax scaled by 1 + 2*gamma(3), a box the ray truly crosses is never culled.
// Invariant 1 (conservative bounds) relies on this test being conservative too.
#pragma once
#include <cmath>
#include <limits>
#include "core/next_float.h"
#include "core/vec.h"

namespace rayes {

// gamma(n) of Higham / pbrt: bound on the relative error of n float operations.
constexpr float gammaBound(int n) {
  constexpr float eps = std::numeric_limits<float>::epsilon() * 0.5f;
  return (n * eps) / (1 - n * eps);
}

struct Box3 {
  Vec3 lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
          std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
          -std::numeric_limits<float>::infinity()};

  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  void extend(Vec3 p) { lo = vmin(lo, p); hi = vmax(hi, p); }
  void extend(const Box3& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
  Vec3 extent() const { return hi - lo; }
  Vec3 center() const { return (lo + hi) * 0.5f; }
  float longestSide() const { return empty() ? 0.0f : maxComponent(extent()); }
  bool contains(Vec3 p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  bool contains(const Box3& b) const { return b.empty() || (contains(b.lo) && contains(b.hi)); }
  // Largest coordinate magnitude: sets the float spacing (ulp) of every point in the box.
  float magnitude() const { return empty() ? 0.0f : maxComponent(vmax(vabs(lo), vabs(hi))); }
  // The float spacing at the box's coordinates (at least their ulp) over its longest side:
  // how coarsely float resolves what lies in the box. 0 for a point; inf for a NaN box.
  float relativeSpacing() const {
    const float side = longestSide();
    return side > 0 ? magnitude() * 0x1p-23f / side : (empty() ? std::numeric_limits<float>::infinity() : 0.0f);
  }
  // The box grown by `err` on every side, rounded outward: it holds every point within `err`
  // of a point of this box, and also every float result that rounded to within `err` of one
  // (half an ulp of the magnitude), so a caller passes only the error of its
  // own computation (docs/design.md, "Precision"). Empty stays empty; non-finite stays so.
  Box3 grownBy(float err) const {
    if (empty()) return *this;
    const float e = err + magnitude() * 0x1p-24f;  // half an ulp: ulp(x) <= x 2^-23
    Box3 r;
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = nextFloatDown(lo[a] - e);
      r.hi[a] = nextFloatUp(hi[a] + e);
    }
    return r;
  }
};

// A ray prepared for repeated box tests: reciprocal direction (IEEE gives +-inf for a zero
// component, which the slab test handles), and the sign of each component.
struct RayBoxQuery {
  Vec3 org, invDir;
  int sign[3];
  explicit RayBoxQuery(Vec3 o, Vec3 d) : org(o) {
    invDir = {1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
    sign[0] = invDir.x < 0; sign[1] = invDir.y < 0; sign[2] = invDir.z < 0;
  }
};

// Conservative slab test. Returns true and the entry distance (clamped to tmin) when the ray
// segment [tmin, tmax] crosses the box. Never NaN: a 0*inf slab (origin on a slab plane of a
// zero direction component) yields NaN which the max/min ordering below discards.
// The axes are written out (x, then y, then z: the same operations in the same order as a loop
// over them): a loop indexing Vec3 by axis compiled to compare-and-select chains, most of this
// test's instructions in the border-region walks (callgrind, bench/history/2026-11.md, "Where the
// bottom level's instructions go").
inline bool intersectBox(const RayBoxQuery& q, const Vec3& lo, const Vec3& hi, float tmin,
                         float tmax, float& tEntry, float& tExit) {
  float t0 = tmin, t1 = tmax;
  auto slab = [&](float l, float h, float org, float invDir, int sign) {
    float tn = ((sign ? h : l) - org) * invDir;
    float tf = ((sign ? l : h) - org) * invDir;
    tf *= 1.0f + 2.0f * gammaBound(3);
    // Written so that a NaN tn/tf leaves t0/t1 unchanged.
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
  };
  slab(lo.x, hi.x, q.org.x, q.invDir.x, q.sign[0]);
  slab(lo.y, hi.y, q.org.y, q.invDir.y, q.sign[1]);
  slab(lo.z, hi.z, q.org.z, q.invDir.z, q.sign[2]);
  tEntry = t0;
  tExit = t1;
  return t0 <= t1;
}

}  // namespace rayes
