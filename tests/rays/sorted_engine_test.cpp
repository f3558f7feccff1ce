// The two-level pipeline (sort by leaf, dice once per leaf, iterate with resumable candidate
// lists) finds exactly the hit a brute-force loop over every leaf finds, for any candidate
// capacity and any number of candidates per ray and iteration: the nearest hit under the order
// (distance, leaf, micro-quad), the distance never less than the ray's entry into the leaf's
// box; shadow rays are occluded exactly when some leaf has a hit before tmax.
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "rays/closed_surfaces.h"
#include "rays/sorted_engine.h"
#include "rays/teapot_on_floor.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kLod = 4;

// The teapot on its floor and a wall behind.
struct World : test::TracedWorld {
  std::vector<std::array<uint32_t, 4>> neighbours;  // SortedEngine::borderNeighbours
  World()
      : TracedWorld(test::teapotOnFloorAnd(
            {std::make_shared<BilinearPatch>(Vec3{-5, 5, 0}, Vec3{5, 5, 0}, Vec3{-5, 5, 6}, Vec3{5, 5, 6})})),
        neighbours(SortedEngine::borderNeighbours(source, top)) {}
};

// Random rays from around the teapot toward it; zero footprint, so every ray uses kLod.
RayBatch randomRays(int n, bool shadow) { return test::raysAtTheTeapot(n, shadow, 11); }

// Every leaf is seen at kLod here, so (SortedEngine::bordersClosedByNeighbours) a leaf's border
// regions are tested except on borders whose Bézier neighbour the ray's line reaches: equal
// levels on both sides of a shared Bézier border leave no slit.
template <class Leaves>
uint8_t skippedBorders(const Leaves& w, const RayBatch& b, int i, uint32_t leaf) {
  const auto& neighbours = w.neighbours;
  if (neighbours.empty()) return 0;
  uint8_t skip = 0;
  for (int e = 0; e < 4; ++e) {
    const uint32_t nb = neighbours[leaf][e];
    float t0, t1;
    if (nb == SortedEngine::kFreeBorder) skip |= uint8_t(1u << e);
    else if (nb != kNoLeaf && intersectBox(RayBoxQuery(b.ray[i].org, b.ray[i].dir()), w.boxes[nb].lo, w.boxes[nb].hi, 0.0f,
                                      std::numeric_limits<float>::infinity(), t0, t1))
      skip |= uint8_t(1u << e);
  }
  return skip;
}

// The distance a hit is kept at: at least the ray's entry into the leaf's box.
float keptDistance(const Box3& box, const RayBatch& b, int i, float t) {
  float t0, t1;
  if (!intersectBox(RayBoxQuery(b.ray[i].org, b.ray[i].dir()), box.lo, box.hi, 0.0f, kInf, t0, t1)) t0 = 0.0f;
  return std::max(t, t0);
}

template <class Leaves>
RayHit bruteForce(const Leaves& w, const RayBatch& b, int i, DiceBuffer& dice) {
  RayHit best;
  for (uint32_t leaf = 0; leaf < w.leaves.size(); ++leaf) {
    dice.dice(*w.leaves[leaf], kLod);
    GridHit h;
    BottomQuery q;
    q.closeBorders = true;  // as the engine does for rays that do not leave from this leaf
    q.skipBorders = skippedBorders(w, b, i, leaf);
    if (!dice.intersect(b.ray[i].org, b.ray[i].dir(), 0.0f, b.ray[i].tmax, kLod, h, q)) continue;
    const float t = keptDistance(w.boxes[leaf], b, i, h.t);
    if (nearerHit(t, leaf, h.quad, best)) {
      best.t = t;
      best.leaf = leaf;
      best.quad = h.quad;
    }
  }
  return best;
}

// Traces `b` through the whole pipeline with the given candidate capacity and mode.
template <class Leaves>
GenerationStats traceAll(const Leaves& w, RayBatch& b, size_t capacity, bool sorted, int perRay = 100) {
  TraceSettings s;
  s.maxLod = kLod;
  s.candidateCapacity = capacity;
  s.sortByLeaf = sorted;
  s.maxCandidatesPerRay = perRay;
  SortedEngine engine(w.top, w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
  return stats;
}

void expectMatchesBruteForce(size_t capacity, bool sorted) {
  World w;
  RayBatch b = randomRays(3000, false);
  const GenerationStats stats = traceAll(w, b, capacity, sorted);
  DiceBuffer dice(kLod);
  int hits = 0;
  for (int i = 0; i < int(b.size()); ++i) {
    const RayHit ref = bruteForce(w, b, i, dice);
    ASSERT_EQ(b.hit[i].leaf, ref.leaf) << "ray " << i;
    if (!ref.valid()) continue;
    ++hits;
    ASSERT_EQ(b.hit[i].t, ref.t) << "ray " << i;
    ASSERT_EQ(b.hit[i].quad, ref.quad) << "ray " << i;
    ASSERT_EQ(b.hit[i].level, kLod);
  }
  EXPECT_GT(hits, 1500);  // most rays hit the teapot, the floor or the wall
  EXPECT_EQ(stats.rays, 3000u);
  if (sorted && capacity < 3000) {
    EXPECT_GT(stats.iterations.size(), 1u);
  }
}

TEST(SortedEngine, SortedPipelineEqualsBruteForce) { expectMatchesBruteForce(1 << 16, true); }

// The candidate sort's scratch is the batch's (RayBatch::sortScratch, which the shading sort
// takes while the batch is shaded): at most one word per candidate slot, and a scratch already
// larger than that is used where it lies, not grown.
TEST(SortedEngine, TheCandidateSortTakesItsScratchFromTheBatch) {
  World w;
  RayBatch b = randomRays(3000, false);
  traceAll(w, b, 3000, true);
  EXPECT_GT(b.sortScratch.bytes(), 0u);
  EXPECT_LE(b.sortScratch.bytes(), 3000 * CandidateSort::scratchBytesPerSlot());
  RayBatch again = randomRays(3000, false);
  const void* lent = again.sortScratch.take<uint64_t>(4000).data();  // 32 000 bytes, more than it needs
  traceAll(w, again, 3000, true);
  EXPECT_EQ(again.sortScratch.bytes(), 4000 * sizeof(uint64_t));
  EXPECT_EQ(static_cast<const void*>(again.sortScratch.take<uint32_t>(1).data()), lent);
  for (size_t i = 0; i < b.size(); ++i) ASSERT_EQ(again.hit[i].leaf, b.hit[i].leaf) << i;
  TraceSettings s;
  s.maxLod = kLod;
  s.candidateCapacity = 3000;
  EXPECT_EQ(SortedEngine(w.top, w.source, s).sortScratchBytesPerRay(), SortedEngine::sortScratchBytesPerRaySlot(s.lod));
}
TEST(SortedEngine, OneCandidateSlotPerRayStillEqualsBruteForce) { expectMatchesBruteForce(3000, true); }
TEST(SortedEngine, FewerSlotsThanRaysStillEqualsBruteForce) { expectMatchesBruteForce(700, true); }
TEST(SortedEngine, RaysTracedAloneEqualBruteForce) { expectMatchesBruteForce(1, false); }

// Coplanar leaves on the plane z = 0, whose boxes are flat: a hit there lies on the box's face,
// and the watertight test's t and the rounded slab entry err in opposite directions about as
// often as not, so hits come out a few roundings before their leaf's entry. Were they kept at
// that t, a ray finished after one leaf (its hit before the next candidate's entry) could
// keep a hit that a later leaf with an earlier unclamped t would have beaten had both come in
// one iteration: the hit would depend on how many candidates a ray gets per iteration.
struct CoplanarLeaves {
  std::vector<PatchPtr> leaves;
  StoredLeaves source;
  std::vector<Box3> boxes;
  std::vector<std::array<uint32_t, 4>> neighbours;
  TopLevelBvh top;
  CoplanarLeaves() {
    for (int k = 0; k < 6; ++k) {  // overlapping quads of different sizes, so their t's round differently
      const float a = -1.0f - 0.37f * float(k), c = 1.0f + 0.29f * float(k);
      leaves.push_back(std::make_shared<BilinearPatch>(Vec3{a, a, 0}, Vec3{c, a, 0}, Vec3{a, c, 0}, Vec3{c, c, 0}));
    }
    for (const auto& l : leaves) boxes.push_back(l->bounds());
    top.build(boxes);
    source = StoredLeaves(leaves);
    neighbours = SortedEngine::borderNeighbours(source, top);
  }
};

TEST(SortedEngine, HitsDoNotDependOnCandidatesPerIteration) {
  CoplanarLeaves w;
  const int n = 3000;
  RayBatch rays;
  rays.resize(n);
  for (int i = 0; i < n; ++i) {
    const RngKey k{uint32_t(i), 0, 0, 12};
    const Vec3 o{-3 + 6 * sampleUniform(k, 0), -3 + 6 * sampleUniform(k, 1), 0.5f + 9 * sampleUniform(k, 2)};
    const Vec3 target{-0.9f + 1.8f * sampleUniform(k, 3), -0.9f + 1.8f * sampleUniform(k, 4), 0};
    rays.setFromNowhere(i, RayKind::Closest, o, target - o, kInf, 0.0f, 0.0f);
  }
  RayBatch one = rays, all = rays;
  traceAll(w, one, 1 << 16, true, 1);
  traceAll(w, all, 1 << 16, true, 100);
  DiceBuffer dice(kLod);
  int beforeEntry = 0;
  for (int i = 0; i < n; ++i) {
    const RayHit ref = bruteForce(w, rays, i, dice);
    ASSERT_TRUE(ref.valid()) << "ray " << i;  // every ray aims inside the smallest quad
    for (const RayBatch* b : {&one, &all}) {
      ASSERT_EQ(b->hit[i].leaf, ref.leaf) << "ray " << i << (b == &one ? ", one candidate per iteration" : "");
      ASSERT_EQ(b->hit[i].t, ref.t) << "ray " << i;
      ASSERT_EQ(b->hit[i].quad, ref.quad) << "ray " << i;
    }
    // How often the clamp decides: the unclamped t of the kept leaf lies before its entry.
    GridHit h;
    dice.dice(*w.leaves[ref.leaf], kLod);
    BottomQuery q;
    q.closeBorders = true;
    q.skipBorders = skippedBorders(w, rays, i, ref.leaf);
    ASSERT_TRUE(dice.intersect(rays.ray[i].org, rays.ray[i].dir(), 0.0f, rays.ray[i].tmax, kLod, h, q));
    beforeEntry += h.t < ref.t;
  }
  EXPECT_GT(beforeEntry, 0);  // the case the clamp exists for does occur here
}

// A border is free (SortedEngine::kFreeBorder: no regions, since no neighbour can leave a crack
// there) exactly when no other leaf's box meets it: a lone curved patch has four; a quad laid
// against the middle of its v = 0 border takes that one away and leaves the other three,
// whose boxes it does not reach.
TEST(SortedEngine, BordersNoOtherLeafMeetsAreFree) {
  std::array<Vec3, 16> cp;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) cp[j * 4 + i] = {i / 3.0f, j / 3.0f, (i % 3 != 0 && j % 3 != 0) ? 0.5f : 0.0f};
  std::vector<PatchPtr> leaves{std::make_shared<BezierPatch>(cp)};
  const auto neighbours = [&] {
    std::vector<Box3> boxes;
    for (const auto& l : leaves) boxes.push_back(l->bounds());
    TopLevelBvh top;
    top.build(boxes);
    return SortedEngine::borderNeighbours(StoredLeaves(leaves), top);
  };
  const uint32_t F = SortedEngine::kFreeBorder;
  ASSERT_EQ(neighbours().size(), 1u);
  EXPECT_EQ(neighbours()[0], (std::array<uint32_t, 4>{F, F, F, F}));
  leaves.push_back(
      std::make_shared<BilinearPatch>(Vec3{0.3f, -1, 0}, Vec3{0.7f, -1, 0}, Vec3{0.3f, 0, 0}, Vec3{0.7f, 0, 0}));
  ASSERT_EQ(neighbours().size(), 2u);
  EXPECT_EQ(neighbours()[0], (std::array<uint32_t, 4>{kNoLeaf, F, F, F}));
  EXPECT_EQ(neighbours()[1], (std::array<uint32_t, 4>{kNoLeaf, kNoLeaf, kNoLeaf, kNoLeaf}));  // flat: no regions
}

// Displaced Bézier leaves are paired by their bases' borders, with the neighbour's border and
// direction (SortedEngine::borderNeighbours' sides): the seam's regions can then be thin where both
// sides are seen at one level (crack_test.cpp). A plain and a displaced patch over one base
// border are not a pair: their border vertices are not alike.
TEST(SortedEngine, DisplacedNeighboursArePairedWithTheirBorderAndDirection) {
  // A curved patch over [x0, x0 + 1] x [0, 1]; `flipV` runs its v the other way.
  auto base = [](float x0, bool flipV) {
    std::array<Vec3, 16> cp;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const int jj = flipV ? 3 - j : j;
        cp[j * 4 + i] = {x0 + i / 3.0f, jj / 3.0f, (i % 3 != 0 && jj % 3 != 0) ? 0.5f : 0.0f};
      }
    return std::make_shared<BezierPatch>(cp);
  };
  NoiseParams noise;
  noise.amplitude = 0.05f;
  const auto displacement = std::make_shared<NoiseDisplacement>(noise);
  auto pairs = [](const std::vector<PatchPtr>& leaves) {
    std::vector<Box3> boxes;
    for (const auto& l : leaves) boxes.push_back(l->bounds());
    TopLevelBvh top;
    top.build(boxes);
    std::vector<std::array<uint8_t, 4>> sides;
    auto out = SortedEngine::borderNeighbours(StoredLeaves(leaves), top, &sides);
    return std::make_pair(out, sides);
  };
  const uint8_t D = SortedEngine::kDisplacedSeam, R = SortedEngine::kReversedSeam;
  {  // u = 1 of the first against u = 0 of the second, both running up in v
    const auto [nb, sides] = pairs({std::make_shared<DisplacedPatch>(base(0, false), displacement),
                                    std::make_shared<DisplacedPatch>(base(1, false), displacement)});
    ASSERT_EQ(nb.size(), 2u);
    EXPECT_EQ(nb[0][1], 1u);
    EXPECT_EQ(nb[1][3], 0u);
    EXPECT_EQ(sides[0][1], uint8_t(3 | D));
    EXPECT_EQ(sides[1][3], uint8_t(1 | D));
  }
  {  // the second runs down in v: the seam is reversed, seen from either side
    const auto [nb, sides] = pairs({std::make_shared<DisplacedPatch>(base(0, false), displacement),
                                    std::make_shared<DisplacedPatch>(base(1, true), displacement)});
    ASSERT_EQ(nb.size(), 2u);
    EXPECT_EQ(nb[0][1], 1u);
    EXPECT_EQ(sides[0][1], uint8_t(3 | D | R));
    EXPECT_EQ(sides[1][3], uint8_t(1 | D | R));
  }
  {  // plain against displaced: no pair
    const auto [nb, sides] = pairs({base(0, false), std::make_shared<DisplacedPatch>(base(1, false), displacement)});
    for (const auto& leaf : nb) EXPECT_NE(leaf[1], 1u);
    if (!nb.empty()) {
      EXPECT_NE(nb[1][3], 0u);
    }
  }
}

// A displaced seam's gap is the same number from either side (SortedEngine::seamGap), so it is
// measured once: both sides name one entry of the seam-gap table (seamKey), and no two seams or
// levels share one. A sphere of displaced Bézier patches, every border a displaced seam.
TEST(SortedEngine, BothSidesOfADisplacedSeamNameOneSeamGapEntry) {
  const auto leaves = test::displacedBezierSphere(3, 0.1f);
  std::vector<Box3> boxes;
  for (const auto& l : leaves) boxes.push_back(l->bounds());
  TopLevelBvh top;
  top.build(boxes);
  std::vector<std::array<uint8_t, 4>> sides;
  const auto nb = SortedEngine::borderNeighbours(StoredLeaves(leaves), top, &sides);
  ASSERT_EQ(nb.size(), leaves.size());
  std::map<std::tuple<uint32_t, int, int, uint32_t>, int> namedBy;  // key -> sides naming it
  size_t displacedSides = 0;
  for (uint32_t leaf = 0; leaf < nb.size(); ++leaf)
    for (int e = 0; e < 4; ++e) {
      if (!(sides[leaf][size_t(e)] & SortedEngine::kDisplacedSeam)) continue;
      ++displacedSides;
      const uint32_t other = nb[leaf][size_t(e)];
      const int across = sides[leaf][size_t(e)] & 3;
      ASSERT_LT(other, nb.size());
      ASSERT_EQ(nb[other][size_t(across)], leaf) << "a seam's far side points back";
      for (int k = 0; k <= BottomQuery::kMaxThinLevel; ++k) {
        const auto mine = SortedEngine::seamKey(leaf, e, other, sides[leaf][size_t(e)], k);
        const auto theirs = SortedEngine::seamKey(other, across, leaf, sides[other][size_t(across)], k);
        EXPECT_EQ(std::tie(mine.leaf, mine.border, mine.level), std::tie(theirs.leaf, theirs.border, theirs.level))
            << "leaf " << leaf << " border " << e << " level " << k;
        EXPECT_EQ(mine.kind, BorderBoundCache::Kind::SeamGap);
        EXPECT_EQ(mine.level, k);
        ++namedBy[{mine.leaf, mine.border, mine.level, mine.segment}];
      }
    }
  EXPECT_EQ(displacedSides, 4 * leaves.size()) << "the sphere is closed: every border a displaced seam";
  EXPECT_EQ(namedBy.size(), displacedSides / 2 * (BottomQuery::kMaxThinLevel + 1));
  for (const auto& [key, count] : namedBy) EXPECT_EQ(count, 2) << "an entry named by " << count << " sides";
}

TEST(SortedEngine, ShadowRaysAreOccludedExactlyWhenSomethingIsInTheWay) {
  World w;
  RayBatch b = randomRays(2000, true);
  const GenerationStats stats = traceAll(w, b, 5000, true);
  DiceBuffer dice(kLod);
  int occluded = 0;
  for (int i = 0; i < int(b.size()); ++i) {
    const bool ref = bruteForce(w, b, i, dice).valid();
    ASSERT_EQ(b.hit[i].valid(), ref) << "ray " << i;
    occluded += ref;
  }
  EXPECT_GT(occluded, 200);
  EXPECT_LT(occluded, 1900);
  EXPECT_EQ(stats.shadowRays, 2000u);
}

// Closest rays in the even slots and shadow rays in the odd ones (the path tracer's layout), in a
// batch of shadow pairs or with a full hit per slot.
RayBatch pairedRays(int n, bool shadowPairs) {
  const RayBatch closest = randomRays(n, false), shadow = randomRays(n, true);
  RayBatch b;
  b.shadowPairs = shadowPairs;
  b.resize(2 * size_t(n));
  for (int k = 0; k < n; ++k) {
    b.ray[2 * size_t(k)] = closest.ray[size_t(k)];
    b.ray[2 * size_t(k) + 1] = shadow.ray[size_t(k)];
  }
  return b;
}

// A shadow slot of a pair keeps only its occluding leaf (RayBatch::shadowPairs): every walk of
// the engine finds the same closest hits and the same occluders (the smallest leaf, as the full
// record orders them) as with a full hit per slot.
TEST(SortedEngine, ShadowPairsKeepTheSameHitsAndOneOccluderLeafPerShadowSlot) {
  World w;
  constexpr int kPaths = 1500;
  struct Walk { size_t capacity; bool sorted; int perRay; };
  for (const Walk walk : {Walk{1 << 16, true, 100}, Walk{700, true, 1}, Walk{1, false, 100}}) {
    RayBatch full = pairedRays(kPaths, false), pairs = pairedRays(kPaths, true);
    ASSERT_EQ(pairs.hit.size(), size_t(kPaths));
    ASSERT_EQ(pairs.occluder.size(), size_t(kPaths));
    traceAll(w, full, walk.capacity, walk.sorted, walk.perRay);
    traceAll(w, pairs, walk.capacity, walk.sorted, walk.perRay);
    int occluded = 0, hits = 0;
    for (size_t i = 0; i < full.size(); ++i) {
      ASSERT_EQ(pairs.occluded(i), full.hit[i].valid()) << "slot " << i << ", capacity " << walk.capacity;
      ASSERT_EQ(pairs.occluderOf(i), full.hit[i].leaf) << "slot " << i << ", capacity " << walk.capacity;
      if (i % 2 == 1) {
        EXPECT_FALSE(pairs.keepsFullHit(i));
        occluded += pairs.occluded(i);
        continue;
      }
      const RayHit &a = full.hit[i], &p = pairs.hitOf(i);
      hits += a.valid();
      ASSERT_EQ(p.t, a.t) << "slot " << i;
      ASSERT_EQ(p.quad, a.quad) << "slot " << i;
      ASSERT_EQ(p.u, a.u) << "slot " << i;
      ASSERT_EQ(p.v, a.v) << "slot " << i;
      ASSERT_EQ(p.nsCode, a.nsCode) << "slot " << i;
      ASSERT_EQ(p.level, a.level) << "slot " << i;
    }
    EXPECT_GT(hits, 750);
    EXPECT_GT(occluded, 150);
    EXPECT_LT(occluded, 1425);
  }
}

TEST(SortedEngine, AClosestRayInAShadowSlotOfAPairIsRefused) {
  World w;
  RayBatch b = pairedRays(4, true);
  b.ray[3] = b.ray[2];  // a closest ray where only a shadow ray's occluder is kept
  EXPECT_THROW(traceAll(w, b, 1 << 10, true), std::logic_error);
}

TEST(SortedEngine, IgnoredLeafIsNeverHitAndInactiveSlotsAreSkipped) {
  World w;
  TraceSettings s;
  s.maxLod = kLod;
  SortedEngine engine(w.top, w.source, s);
  RayBatch b;
  b.resize(2);
  const uint32_t wall = uint32_t(w.leaves.size() - 1);
  b.set(0, RayKind::Closest, {0, -20, 4}, {0, 1, 0}, kInf, 0, 0, wall, kNoLeaf, 0, 0.0f);  // above the teapot, at the wall
  b.ray[1].kind = RayKind::Inactive;
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
  EXPECT_FALSE(b.hit[0].valid());
  EXPECT_FALSE(b.hit[1].valid());
  EXPECT_EQ(stats.rays, 1u);
}

}  // namespace
}  // namespace rayes
