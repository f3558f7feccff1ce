// Shared by the top-level tests: deterministic random scenes and rays, and the brute-force
// reference (every leaf box the ray crosses, by intersectBox, sorted by (entry, leaf)).
#pragma once
#include <algorithm>
#include <cstdint>
#include <limits>
#include <ostream>
#include <vector>
#include "core/box.h"
#include "core/rng.h"
#include "toplevel/toplevel_bvh.h"

namespace rayes {
// In namespace rayes so that ADL finds them (vector ==, gtest printing).
inline bool operator==(const Candidate& a, const Candidate& b) {
  return a.leaf == b.leaf && a.entry == b.entry;
}
inline void PrintTo(const Candidate& c, std::ostream* os) {
  *os << "{leaf " << c.leaf << ", entry " << c.entry << "}";
}
}  // namespace rayes

namespace rayes::testing {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Counter-based so the scenes are the same on every platform (std distributions are not).
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  float uniform() { return bitsToUnitFloat(mix64(state_++ * 0x9e3779b97f4a7c15ull + 1)); }
  float uniform(float a, float b) { return a + (b - a) * uniform(); }
  int below(int n) { return int(uniform() * float(n)) % n; }
 private:
  uint64_t state_;
};

inline bool candidateLess(const Candidate& a, const Candidate& b) {
  return a.entry < b.entry || (a.entry == b.entry && a.leaf < b.leaf);
}

// Boxes in [0, 100]^3 at scale 1: mostly small, some flat in one axis, some huge, a few empty.
inline std::vector<Box3> randomBoxes(int n, uint64_t seed, float scale = 1, float offset = 0) {
  Rng rng(seed);
  std::vector<Box3> boxes(n);
  for (Box3& b : boxes) {
    const float kind = rng.uniform();
    const float size = kind < 0.05f ? rng.uniform(50, 300) : rng.uniform(0.05f, 6);
    Vec3 lo{rng.uniform(0, 100), rng.uniform(0, 100), rng.uniform(0, 100)};
    Vec3 ext{size * rng.uniform(0.2f, 1), size * rng.uniform(0.2f, 1), size * rng.uniform(0.2f, 1)};
    if (kind > 0.9f) ext[rng.below(3)] = 0;  // flat, like a planar patch's box
    b.lo = lo * scale + Vec3{offset, offset, offset};
    b.hi = (lo + ext) * scale + Vec3{offset, offset, offset};
    if (kind > 0.99f) std::swap(b.lo, b.hi);  // empty
  }
  return boxes;
}

struct TestRay {
  Vec3 org, dir;
  float tmin = 0, tmax = kInf;
};

// Rays from around and inside the scene (many start inside boxes), some axis-parallel, some
// starting exactly on a box plane with a zero direction component (the 0 * inf slab case).
inline std::vector<TestRay> randomRays(int n, uint64_t seed, const std::vector<Box3>& boxes,
                                       float scale = 1, float offset = 0) {
  Rng rng(seed);
  std::vector<TestRay> rays(n);
  for (TestRay& r : rays) {
    const Vec3 o{rng.uniform(-30, 130), rng.uniform(-30, 130), rng.uniform(-30, 130)};
    r.org = o * scale + Vec3{offset, offset, offset};
    r.dir = normalize(Vec3{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
    const float kind = rng.uniform();
    if (kind < 0.3f) {  // axis-parallel: one or two zero components (signed zeros too)
      r.dir[rng.below(3)] = rng.uniform() < 0.5f ? 0.0f : -0.0f;
      if (kind < 0.1f) r.dir[rng.below(3)] = 0.0f;
    }
    if (kind < 0.05f) {  // on a box's slab plane, moving parallel to it
      const Box3& b = boxes[rng.below(int(boxes.size()))];
      const int a = rng.below(3);
      r.org[a] = rng.uniform() < 0.5f ? b.lo[a] : b.hi[a];
      r.dir[a] = 0;
      if (r.dir == Vec3{0, 0, 0}) r.dir[(a + 1) % 3] = 1;
    }
    if (r.dir == Vec3{0, 0, 0}) r.dir.x = 1;
    if (rng.uniform() < 0.2f) r.tmin = rng.uniform(0, 40) * scale;
    if (rng.uniform() < 0.2f) r.tmax = r.tmin + rng.uniform(0, 80) * scale;
  }
  return rays;
}

inline std::vector<Candidate> bruteForce(const std::vector<Box3>& boxes, const TestRay& r) {
  const RayBoxQuery q(r.org, r.dir);
  std::vector<Candidate> all;
  for (size_t i = 0; i < boxes.size(); ++i) {
    float entry, exit;
    if (!boxes[i].empty() && intersectBox(q, boxes[i].lo, boxes[i].hi, r.tmin, r.tmax, entry, exit))
      all.push_back({uint32_t(i), entry});
  }
  std::sort(all.begin(), all.end(), candidateLess);
  return all;
}

// One collect() call from a resume point.
struct Collected {
  std::vector<Candidate> list;
  float nextEntry = 0;
};
inline Collected collectOnce(const TopLevelBvh& bvh, const TestRay& r, int maxCount,
                             TraversalScratch& scratch, float resumeEntry = -kInf,
                             uint32_t resumeLeaf = 0) {
  Collected c;
  c.list.resize(size_t(std::max(maxCount, 0)));
  const int n = bvh.collect(r.org, r.dir, r.tmin, r.tmax, resumeEntry, resumeLeaf, c.list.data(),
                            maxCount, c.nextEntry, scratch);
  c.list.resize(size_t(n));
  return c;
}

}  // namespace rayes::testing
