// Private to the top level (and its tests): the node layout of TopLevelBvh and the 4-wide
// slab test. Not part of the contract in toplevel_bvh.h.
#pragma once
#include <cstdint>
#include <span>
#include "core/box.h"

namespace rayes {
class TopLevelBvh;
}

namespace rayes::toplevel {

// A child reference. The leaf flag is the top bit so that, compared as unsigned integers,
// every inner-node ref orders before every leaf ref and leaf refs order by leaf id; the
// traversal heap relies on exactly this (see collect()).
constexpr uint32_t kLeafFlag = 0x80000000u;
constexpr uint32_t kMaxLeafId = 0x7ffffffeu;      // kEmptyRef's id is never a real leaf
constexpr uint32_t kEmptyRef = 0xffffffffu;       // unused child slot (inverted bounds)
constexpr uint32_t kNoRoot = 0xffffffffu;         // tree over zero non-empty boxes

constexpr bool isLeafRef(uint32_t ref) { return (ref & kLeafFlag) != 0; }
constexpr uint32_t leafRef(uint32_t leafId) { return leafId | kLeafFlag; }
constexpr uint32_t refLeafId(uint32_t ref) { return ref & ~kLeafFlag; }

// Four child boxes in SoA form (lo[axis][child]) so the slab test below runs over the four
// children at once, plus their refs. Slots at index >= count hold inverted boxes
// (lo = +inf, hi = -inf), which the slab test rejects for every ray (for each axis one of
// the two slab distances is +-inf with the wrong sign and none is NaN), so the traversal
// needs no per-slot count check. 112 bytes of data, padded to two cache lines.
struct alignas(64) Node4 {
  float lo[3][4];
  float hi[3][4];
  uint32_t child[4];
  uint32_t count;
};
static_assert(sizeof(Node4) == 128);

// intersectBox (core/box.h) for the four children of a node, operation for operation in the
// same order, so that a leaf's entry distance here is bit-identical to intersectBox on that
// leaf's box: the traversal order and the brute-force reference order then agree exactly,
// and the monotonicity argument in collect() holds for the rounded values.
// Returns a bit mask of the children whose box the segment [tmin, tmax] crosses.
inline unsigned intersectChildren(const Node4& n, const RayBoxQuery& q, float tmin, float tmax,
                                  float tEntry[4], float tExit[4]) {
  constexpr float kFarScale = 1.0f + 2.0f * gammaBound(3);
  float t0[4] = {tmin, tmin, tmin, tmin};
  float t1[4] = {tmax, tmax, tmax, tmax};
  for (int a = 0; a < 3; ++a) {
    const float* nearPlane = q.sign[a] ? n.hi[a] : n.lo[a];
    const float* farPlane = q.sign[a] ? n.lo[a] : n.hi[a];
    const float o = q.org[a], inv = q.invDir[a];
    for (int i = 0; i < 4; ++i) {
      const float tn = (nearPlane[i] - o) * inv;
      float tf = (farPlane[i] - o) * inv;
      tf *= kFarScale;
      t0[i] = tn > t0[i] ? tn : t0[i];
      t1[i] = tf < t1[i] ? tf : t1[i];
    }
  }
  unsigned mask = 0;
  for (int i = 0; i < 4; ++i) {
    tEntry[i] = t0[i];
    tExit[i] = t1[i];
    mask |= unsigned(t0[i] <= t1[i]) << i;
  }
  return mask;
}

// Read access to a built tree, for tests and statistics (a friend of TopLevelBvh).
struct Inspector {
  static std::span<const Node4> nodes(const TopLevelBvh& bvh);
  static uint32_t root(const TopLevelBvh& bvh);  // a node index, a leaf ref, or kNoRoot
};

}  // namespace rayes::toplevel
