// Private to the top level (and its tests): the node layout of TopLevelBvh and the 4-wide
// slab test. Not part of the contract in toplevel_bvh.h.
#pragma once
#include <cstdint>
#include <span>
#include "core/box4.h"

namespace rayes {
class TopLevelBvh;
}

namespace rayes::toplevel {

// A child reference: a node index, or a leaf id with the top bit set (so 31-bit leaf ids).
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

// core/box4.h's slab test on the four children of a node, so a leaf's entry distance is
// bit-identical to intersectBox on its box: the traversal order and the brute-force reference
// agree exactly, and the monotonicity argument in collect() holds for the rounded values.
// Returns a bit mask of the children whose box the segment [tmin, tmax] crosses.
inline unsigned intersectChildren(const Node4& n, const RayBox4Query& q, float tmin, float tmax,
                                  float tEntry[4], float tExit[4]) {
  __m128 nearPlane[3], farPlane[3];
  for (int a = 0; a < 3; ++a) {
    nearPlane[a] = _mm_load_ps(q.sign[a] ? n.hi[a] : n.lo[a]);
    farPlane[a] = _mm_load_ps(q.sign[a] ? n.lo[a] : n.hi[a]);
  }
  __m128 t0, t1;
  const unsigned mask = intersectBox4(q, nearPlane, farPlane, _mm_set1_ps(tmin), _mm_set1_ps(tmax), t0, t1);
  _mm_storeu_ps(tEntry, t0);
  _mm_storeu_ps(tExit, t1);
  return mask;
}

// Read access to a built tree, for tests and statistics (a friend of TopLevelBvh).
struct Inspector {
  static std::span<const Node4> nodes(const TopLevelBvh& bvh);
  static uint32_t root(const TopLevelBvh& bvh);  // a node index, a leaf ref, or kNoRoot
};

}  // namespace rayes::toplevel
