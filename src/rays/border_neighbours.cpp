// The SortedEngine's knowledge of what lies across each leaf border, and what a ray may skip
// because of it. Found once at set-up (borderNeighbours: which static Bézier leaves, plain or
// displaced, share a border, and which borders are free), then asked per ray and leaf
// (bordersClosedByNeighbours: the crack-closing regions a ray need not test, or may test thin,
// with seamGap measuring a displaced seam's slit). Apart from the pipeline because it is one
// subject of its own: crack closure between neighbours (docs/architecture.md, "Coarser side only").
#include "rays/sorted_engine.h"
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include "geometry/displaced_patch.h"

namespace rayes {

// Two static Bézier leaves share border e and e' when the border curves have the same end
// points (in either order) and the same midpoint: canonical border evaluation makes these
// bits equal exactly when the border control rows are the same. A border with no partner or
// more than one keeps its regions, unless it is free (no other leaf's box meets its box).
std::vector<std::array<uint32_t, 4>> SortedEngine::borderNeighbours(const LeafSource& leaves, const TopLevelBvh& top,
                                                                    std::vector<std::array<uint8_t, 4>>* sideOut) {
  using Key = std::array<float, 9>;
  struct Side {
    uint32_t leaf;
    int e;
    bool reversed;   // the key's first point is the border's end, not its start
    bool displaced;
  };
  std::map<Key, std::vector<Side>> borders;
  const float corner[4][4] = {{0, 0, 1, 0}, {1, 0, 1, 1}, {0, 1, 1, 1}, {0, 0, 0, 1}};  // (u0, v0, u1, v1)
  for (uint32_t leaf = 0; leaf < leaves.size(); ++leaf) {
    const LeafFacts f = leaves.facts(leaf);
    const bool displaced = std::strcmp(f.kind, "displaced-bezier") == 0;
    if (f.timeSamples != 1 || (!displaced && std::strcmp(f.kind, "bezier") != 0) || !f.borderClosure) continue;
    const PatchPtr patch = leaves.patch(leaf);
    // A displaced leaf is paired by its base: P and (for noise of position) h agree across
    // the seam where the bases' borders do.
    const Patch& p = displaced ? static_cast<const DisplacedPatch&>(*patch).base() : *patch;
    for (int e = 0; e < 4; ++e) {
      const float* c = corner[e];
      Vec3 a = p.evaluate(c[0], c[1]).p, z = p.evaluate(c[2], c[3]).p;
      const Vec3 mid = p.evaluate(0.5f * (c[0] + c[2]), 0.5f * (c[1] + c[3])).p;
      const bool reversed = std::tie(z.x, z.y, z.z) < std::tie(a.x, a.y, a.z);
      if (reversed) std::swap(a, z);
      borders[Key{a.x, a.y, a.z, mid.x, mid.y, mid.z, z.x, z.y, z.z}].push_back({leaf, e, reversed, displaced});
    }
  }
  std::vector<std::array<uint32_t, 4>> out;
  std::vector<std::array<uint8_t, 4>> sideOf;
  for (const auto& [key, sides] : borders) {
    // A pair of one kind: a plain and a displaced patch on one base border do not meet.
    if (sides.size() != 2 || sides[0].leaf == sides[1].leaf || sides[0].displaced != sides[1].displaced) continue;
    if (out.empty()) {
      out.assign(leaves.size(), {kNoLeaf, kNoLeaf, kNoLeaf, kNoLeaf});
      sideOf.assign(leaves.size(), {0, 0, 0, 0});
    }
    for (int s = 0; s < 2; ++s) {
      const Side& me = sides[size_t(s)];
      const Side& other = sides[size_t(1 - s)];
      out[me.leaf][size_t(me.e)] = other.leaf;
      sideOf[me.leaf][size_t(me.e)] = uint8_t(other.e | (me.reversed != other.reversed ? kReversedSeam : 0) |
                                              (me.displaced ? kDisplacedSeam : 0));
    }
  }
  // Free borders, found in parallel (a generated leaf's patch is made for it and dropped):
  // bit e of freeBorders[leaf] for border e.
  std::vector<uint8_t> freeBorders(leaves.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 256), [&](const auto& r) {
    for (size_t leaf = r.begin(); leaf != r.end(); ++leaf) {
      if (!leaves.facts(leaf).borderClosure) continue;
      const PatchPtr patch = leaves.patch(leaf);
      const Patch& p = *patch;
      for (int e = 0; e < 4; ++e) {
        if (!out.empty() && out[leaf][e] != kNoLeaf) continue;
        const float* c = corner[e];
        Box3 border;
        for (int sample = 0; sample < p.timeSamples(); ++sample)
          border.extend(p.boundsOverAt(sample, c[0], c[2], c[1], c[3]));
        if (!top.anyOtherLeafMeets(border, uint32_t(leaf))) freeBorders[leaf] |= uint8_t(1u << e);
      }
    }
  });
  for (uint32_t leaf = 0; leaf < leaves.size(); ++leaf)
    for (int e = 0; e < 4; ++e) {
      if (!(freeBorders[leaf] >> e & 1u)) continue;
      if (out.empty()) {
        out.assign(leaves.size(), {kNoLeaf, kNoLeaf, kNoLeaf, kNoLeaf});
        sideOf.assign(leaves.size(), {0, 0, 0, 0});
      }
      out[leaf][e] = kFreeBorder;
    }
  if (sideOut) *sideOut = std::move(sideOf);
  return out;
}

void SortedEngine::bordersClosedByNeighbours(const RayBatch& b, uint32_t i, const RayBoxQuery& q, uint32_t leaf,
                                             int level, const Patch& patch, const DiceBuffer& dice,
                                             BottomQuery& query) const {
  if (borderNeighbour_.empty()) return;
  for (int e = 0; e < 4; ++e) {
    const uint32_t nb = borderNeighbour_[leaf][e];
    if (nb == kFreeBorder) {
      query.skipBorders |= uint8_t(1u << e);
      continue;
    }
    if (nb == kNoLeaf || nb == b.ray[i].originLeaf() || nb == b.ray[i].ignoreLeaf) continue;
    float entry;
    if (!crossesLeafBox(q, nb, entry)) continue;
    const int other = levelFor(b, i, nb, entry);  // as the neighbour's own runs compute it
    if (!(borderSide_[leaf][e] & kDisplacedSeam)) {
      if (other <= level) query.skipBorders |= uint8_t(1u << e);
    } else if (other == level && level <= BottomQuery::kMaxThinLevel) {
      const double gap = seamGap(leaf, patch, dice, e, level);
      if (!std::isfinite(gap)) continue;  // a vertex that is not finite: the full region stays
      query.thinBorders |= uint8_t(1u << e);
      query.thinRadius[e] = gap;
    }
  }
}

namespace {
// The parameters of the point at t along border e (DiceBuffer's numbering).
std::pair<float, float> borderPoint(int e, float t) {
  switch (e) {
    case 0: return {t, 0.0f};
    case 1: return {1.0f, t};
    case 2: return {t, 1.0f};
    default: return {0.0f, t};
  }
}
}  // namespace

double SortedEngine::seamGap(uint32_t leaf, const Patch& patch, const DiceBuffer& dice, int e, int k) const {
  SeamGapMemo& memo = seamGapMemo_.local();
  if (memo.leaf != leaf) {
    memo.leaf = leaf;
    memo.known = 0;
  }
  const uint32_t bit = 1u << (e * 8 + k);
  if (memo.known & bit) return memo.gap[e][k];
  double gap;
  const bool cached = settings_.borderBoundEntries > 0;
  const BorderBoundCache::Key key = seamKey(leaf, e, borderNeighbour_[leaf][size_t(e)], borderSide_[leaf][size_t(e)], k);
  if (!(cached && seamGaps_.find(key, gap))) {
    gap = measuredSeamGap(leaf, patch, dice, e, k);
    if (cached) seamGaps_.insert(key, gap);
  }
  memo.gap[e][k] = gap;
  memo.known |= bit;
  return gap;
}

double SortedEngine::measuredSeamGap(uint32_t leaf, const Patch& patch, const DiceBuffer& dice, int e, int k) const {
  const uint32_t nb = borderNeighbour_[leaf][size_t(e)];
  const uint8_t side = borderSide_[leaf][size_t(e)];
  const int eb = side & 3;
  const bool reversed = (side & kReversedSeam) != 0;
  const PatchPtr other = leaves_.patch(nb);
  const uint32_t n = 1u << k;
  // This side's level-k border vertices are the grid's, which is evaluate() bit for bit (its
  // parameters v / 2^k are exact at any level m >= k): evaluating them again was half of this
  // function's cost (a displaced point costs ~4,900 instructions).
  const bool fromGrid = !dice.moving() && k <= dice.level();
  const int last = fromGrid ? (1 << dice.level()) : 0, step = fromGrid ? 1 << (dice.level() - k) : 0;
  double worst = 0;
  for (uint32_t v = 0; v <= n; ++v) {
    const float t = float(v) / float(n), tb = reversed ? float(n - v) / float(n) : t;  // exact: n is a power of two
    const auto [u0, v0] = borderPoint(e, t);
    const auto [u1, v1] = borderPoint(eb, tb);
    Vec3 a;
    if (fromGrid) {
      const int s = int(v) * step;
      switch (e) {
        case 0: a = dice.position(s, 0); break;
        case 1: a = dice.position(last, s); break;
        case 2: a = dice.position(s, last); break;
        default: a = dice.position(0, s); break;
      }
    } else {
      a = patch.evaluate(u0, v0).p;
    }
    const Vec3 c = other->evaluate(u1, v1).p;
    const double dx = double(a.x) - c.x, dy = double(a.y) - c.y, dz = double(a.z) - c.z;
    const double d2 = dx * dx + dy * dy + dz * dz;
    worst = d2 > worst || std::isnan(d2) ? d2 : worst;  // a NaN stays: the caller keeps the full region
  }
  return std::sqrt(worst) * (1.0 + 1e-9);  // the rounding of the sum and the root (double, on float inputs)
}

}  // namespace rayes
