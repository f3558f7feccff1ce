// The Embree engine finds the SortedEngine's hits when both see the same tessellation: every
// patch at one fixed level, the Rayes rays with zero footprint (so at that level) and without
// border regions (the Embree engine has none). Same leaf, t within the float error of the two
// triangle tests, (u, v) within one micro-quad, the same triangle's normal; shadow rays occluded
// alike; with motion blur; the ignored leaf never hit. Also its auto level rule and its memory
// refusal.
#include <cfloat>
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/error.h"
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/moving_patch.h"
#include "rays/embree_engine.h"
#include "rays/teapot_on_floor.h"
#include "rays/sorted_engine.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kLod = 4;

// A body patch of the teapot, doubled in size, in front of it, moving in x and z.
std::vector<PatchPtr> movingPatch() {
  const auto teapot = loadBezierPatchFile(std::string(RAYES_SOURCE_DIR) + "/scenes/teapot.bpt");
  std::vector<PatchPtr> samples;
  for (const Vec3 shift : {Vec3{-3, -4, 0.0f}, Vec3{-1, -4, 1.0f}, Vec3{1, -4, 0.0f}}) {
    auto cp = teapot[4];
    for (Vec3& p : cp) p = p * 2.0f + shift;
    samples.push_back(std::make_shared<BezierPatch>(cp));
  }
  return {std::make_shared<MovingPatch>(samples, std::vector<float>{0.0f, 0.5f, 1.0f})};
}

// The teapot, a floor of four quads and, if `moving`, the moving patch.
struct World : test::TracedWorld {
  explicit World(bool moving) : TracedWorld(test::teapotOnFloorAnd(moving ? movingPatch() : std::vector<PatchPtr>{})) {}
};

// Rays from a circle around the scene toward random points of `target` (default: the middle of
// the scene).
RayBatch randomRays(int n, RayKind kind, uint32_t seed, Box3 target = {{-3, -3, 0}, {3, 3, 3}}) {
  RayBatch b;
  b.resize(n);
  for (int i = 0; i < n; ++i) {
    const RngKey k{uint32_t(i), seed, 0, 23};
    const float a = 6.2831853f * sampleUniform(k, 0);
    const Vec3 o{7 * std::cos(a), 7 * std::sin(a), 0.5f + 5 * sampleUniform(k, 1)};
    const Vec3 e = target.extent();
    const Vec3 to = target.lo + Vec3{e.x * sampleUniform(k, 2), e.y * sampleUniform(k, 3), e.z * sampleUniform(k, 4)};
    b.set(i, kind, o, normalize(to - o), kind == RayKind::Shadow ? 8.0f : kInf, 0.0f, 0.0f, kNoLeaf,
          kNoLeaf, 0, sampleUniform(k, 5));
  }
  return b;
}

void traceRayes(const World& w, RayBatch& b) {
  TraceSettings s;
  s.maxLod = kLod;
  s.closeBorders = false;
  SortedEngine engine(w.top, w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
}

// Traces `b` with every patch of `w` at kLod, with Embree's watertight triangle test
// (EmbreeSettings::robust): its default test can let a ray through an edge two micro-triangles
// share (with 48-bit ray directions, ray 17519 of stream 23 met one: a hit 0.32 farther, on the
// leaf's far side), which a ray-for-ray comparison would report as a different hit.
GenerationStats traceEmbree(const World& w, RayBatch& b) {
  EmbreeSettings s;
  s.maxLod = kLod;
  s.robust = true;
  EmbreeEngine engine(w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
  return stats;
}

// Both engines intersect the same float triangle. Rayes's watertight test computes t from the
// vertices translated to the ray origin; Embree's as (N . (v0 - o)) / (N . d) with N a cross
// product. Each carries a few roundings (< 8 eps) of the magnitudes involved, |origin| + |hit
// point| over |dir| (1: the decoded direction is unit, t a distance), and Embree's quotient
// amplifies them by
// 1 / |cos| of the angle between the ray and the triangle's normal. Two tests: 16 eps / |cos|.
float tBound(const RayBatch& b, int i, const RayHit& h) {
  const Vec3 p = b.ray[i].org + b.ray[i].dir() * h.t;
  const float cosine = std::fabs(dot(h.ng(), b.ray[i].dir())) / length(b.ray[i].dir());
  return 16 * FLT_EPSILON * (length(b.ray[i].org) + length(p)) / length(b.ray[i].dir()) / std::max(cosine, 1e-6f);
}

void expectSameClosestHits(bool moving) {
  const World w(moving);
  // With motion, half the rays aim at the moving patch's box.
  RayBatch rayes = randomRays(20000, RayKind::Closest, moving), embree = rayes;
  if (moving) {
    const RayBatch at = randomRays(10000, RayKind::Closest, 3, w.leaves.back()->bounds());
    for (int i = 0; i < 10000; ++i)
      rayes.set(i, RayKind::Closest, at.ray[i].org, at.ray[i].dir(), kInf, 0.0f, 0.0f, kNoLeaf, kNoLeaf, 0, at.time[i]);
    embree = rayes;
  }
  traceRayes(w, rayes);
  EXPECT_EQ(traceEmbree(w, embree).rays, embree.size());
  int hits = 0, movingHits = 0;
  const float quad = 1.0f / float(1 << kLod);
  for (int i = 0; i < int(rayes.size()); ++i) {
    const RayHit &r = rayes.hit[i], &e = embree.hit[i];
    ASSERT_EQ(r.valid(), e.valid()) << "ray " << i;
    if (!r.valid()) continue;
    ++hits;
    movingHits += r.leaf == w.leaves.size() - 1 && moving;
    ASSERT_EQ(r.leaf, e.leaf) << "ray " << i;
    EXPECT_NEAR(r.t, e.t, tBound(rayes, i, r)) << "ray " << i;
    EXPECT_NEAR(r.u, e.u, quad) << "ray " << i;
    EXPECT_NEAR(r.v, e.v, quad) << "ray " << i;
    EXPECT_EQ(e.level, kLod);
    // The same triangle, the same way round. The shading normals blend the same corner
    // normals at (s, r) that differ by the rounding of two triangle tests: within the angle
    // the corners span, under 8 degrees (cos 0.99) on these patches at level 4.
    EXPECT_GT(dot(r.ng(), e.ng()), 1 - 1e-4f) << "ray " << i;
    EXPECT_GT(dot(r.ns(), e.ns()), 0.99f) << "ray " << i;
  }
  EXPECT_GT(hits, 10000);
  if (moving) {
    EXPECT_GT(movingHits, 2000);
  }
}

TEST(EmbreeEngine, ClosestHitsEqualTheRayesTracerAtTheSameLevel) { expectSameClosestHits(false); }
TEST(EmbreeEngine, ClosestHitsEqualTheRayesTracerWithMotionBlur) { expectSameClosestHits(true); }

TEST(EmbreeEngine, ShadowRaysAreOccludedLikeTheRayesTracer) {
  const World w(true);
  RayBatch rayes = randomRays(20000, RayKind::Shadow, 7), embree = rayes;
  traceRayes(w, rayes);
  traceEmbree(w, embree);
  int occluded = 0;
  for (int i = 0; i < int(rayes.size()); ++i) {
    ASSERT_EQ(rayes.hit[i].valid(), embree.hit[i].valid()) << "ray " << i;
    occluded += rayes.hit[i].valid();
  }
  EXPECT_GT(occluded, 2000);
  EXPECT_LT(occluded, 18000);
}

// In a batch of shadow pairs (RayBatch::shadowPairs) the odd slots keep an occluder only: the
// closest hits of the even slots and the shadow rays' occlusion are those of a full batch.
TEST(EmbreeEngine, ShadowPairsKeepTheSameHitsAndOcclusion) {
  const World w(false);
  constexpr int kPaths = 5000;
  const RayBatch closest = randomRays(kPaths, RayKind::Closest, 5), shadow = randomRays(kPaths, RayKind::Shadow, 6);
  RayBatch full, pairs;
  pairs.shadowPairs = true;
  for (RayBatch* b : {&full, &pairs}) {
    b->resize(2 * size_t(kPaths));
    for (size_t k = 0; k < size_t(kPaths); ++k) {
      b->ray[2 * k] = closest.ray[k];
      b->ray[2 * k + 1] = shadow.ray[k];
    }
    traceEmbree(w, *b);
  }
  int occluded = 0;
  for (size_t i = 0; i < full.size(); ++i) {
    ASSERT_EQ(pairs.occluded(i), full.hit[i].valid()) << "slot " << i;
    if (i % 2 == 1) {
      occluded += pairs.occluded(i);
      continue;
    }
    ASSERT_EQ(pairs.hitOf(i).leaf, full.hit[i].leaf) << "slot " << i;
    ASSERT_EQ(pairs.hitOf(i).t, full.hit[i].t) << "slot " << i;
    ASSERT_EQ(pairs.hitOf(i).u, full.hit[i].u) << "slot " << i;
  }
  EXPECT_GT(occluded, 500);
  EXPECT_LT(occluded, 4500);
}

TEST(EmbreeEngine, IgnoredLeafIsNeverHitAndInactiveSlotsAreSkipped) {
  const World w(false);
  RayBatch b;
  b.resize(4);
  const uint32_t floor = uint32_t(w.leaves.size() - 1);  // the quad at x, y in [0, 5]
  b.set(0, RayKind::Closest, {2, 2, 5}, {0, 0, -1}, kInf, 0, 0, floor, kNoLeaf, 0, 0.0f);
  b.set(1, RayKind::Shadow, {2, 2, 5}, {0, 0, -1}, 10, 0, 0, floor, kNoLeaf, 0, 0.0f);
  b.setFromNowhere(2, RayKind::Shadow, {2, 2, 5}, {0, 0, -1}, 10, 0, 0);
  b.ray[3].kind = RayKind::Inactive;
  const GenerationStats stats = traceEmbree(w, b);
  EXPECT_FALSE(b.hit[0].valid());
  EXPECT_FALSE(b.hit[1].valid());
  EXPECT_TRUE(b.hit[2].valid());
  EXPECT_FALSE(b.hit[3].valid());
  EXPECT_EQ(stats.rays, 3u);
  EXPECT_EQ(stats.shadowRays, 2u);
}

TEST(EmbreeEngine, BatchesOfAnySizeAreTracedWhole) {
  // Rays go to Embree in fixed-size chunks; a batch of many chunks (and a ragged end) is traced
  // whole, whatever ranges the scheduler makes.
  const World w(false);
  RayBatch b;
  const int n = 300001;
  b.resize(n);
  for (int i = 0; i < n; ++i) b.setFromNowhere(i, RayKind::Closest, {2, 2, 5}, {0, 0, -1}, kInf, 0, 0);
  traceEmbree(w, b);
  int hits = 0;
  for (int i = 0; i < n; ++i) hits += b.hit[i].valid() && b.hit[i].t == 5.0f;
  EXPECT_EQ(hits, n);
}

TEST(EmbreeEngine, RaysItCannotTraceHitNothing) {
  const World w(false);
  RayBatch b;
  b.resize(3);
  b.setFromNowhere(0, RayKind::Closest, {2, 2, 5}, {0, 0, 0}, kInf, 0, 0);      // zero direction
  b.setFromNowhere(1, RayKind::Closest, {kInf, 2, 5}, {0, 0, -1}, kInf, 0, 0);  // infinite origin
  b.setFromNowhere(2, RayKind::Closest, {2, 2, 5}, {0, 0, -1}, 0, 0, 0);        // empty interval
  traceEmbree(w, b);
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(b.hit[i].valid()) << i;
}

TEST(EmbreeEngine, AutoLevelIsTheFootprintRuleAtTheBoxsNearestDistance) {
  const Box3 box{{1, -1, -1}, {3, 1, 1}};
  CameraFootprint cam{{0, 0, 0}, 0.0f, 0.01f};
  // Nearest distance 1: footprint 0.01; size 2 needs 2 / 2^m <= 0.01, m = 8.
  EXPECT_EQ(EmbreeEngine::autoLevel(box, 2.0f, cam, 10), 8);
  EXPECT_EQ(EmbreeEngine::autoLevel(box, 2.0f, cam, 6), 6);
  // The lens radius brings the box nearer: distance 0.5, footprint 0.005, m = 9.
  cam.apertureRadius = 0.5f;
  EXPECT_EQ(EmbreeEngine::autoLevel(box, 2.0f, cam, 10), 9);
  // A camera inside the box: zero distance, the finest level.
  cam = {{2, 0, 0}, 0.0f, 0.01f};
  EXPECT_EQ(EmbreeEngine::autoLevel(box, 2.0f, cam, 10), 10);
}

TEST(EmbreeEngine, TimeStepsPutEveryKeyframeOnTheGrid) {
  auto quad = std::make_shared<BilinearPatch>(Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0});
  EXPECT_EQ(EmbreeEngine::timeSteps(*quad), 1);
  EXPECT_EQ(EmbreeEngine::timeSteps(MovingPatch({quad, quad, quad}, {0.0f, 0.5f, 1.0f})), 3);
  EXPECT_EQ(EmbreeEngine::timeSteps(MovingPatch({quad, quad}, {0.25f, 1.0f})), 5);
  EXPECT_EQ(EmbreeEngine::timeSteps(MovingPatch({quad, quad}, {0.0f, 1.0f / 3.0f})), 4);
}

TEST(EmbreeEngine, RefusesATessellationOverTheMemoryLimitBeforeAllocating) {
  const World w(false);
  EmbreeSettings s;
  s.maxLod = 12;  // 37 patches x 4097^2 vertices x 60 B: 37 GB
  s.memoryLimit = size_t(1) << 30;
  try {
    EmbreeEngine engine(w.source, s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "--memory-limit");
    EXPECT_NE(std::string(e.what()).find("than the limit of 1024 MiB"), std::string::npos) << e.what();
  }
  s.maxLod = 6;
  EmbreeEngine small(w.source, s);
  const EngineStats st = small.engineStats();
  EXPECT_EQ(st.micropolygons, w.leaves.size() << 12);
  EXPECT_EQ(st.vertices, w.leaves.size() * 65 * 65);
  // The estimate holds what was allocated: our vertices and normals, and Embree's peak.
  EXPECT_GE(st.estimatedBytes, st.vertexBytes - sizeof(Vec3) + st.embreePeakBytes);
  EXPECT_GT(st.embreeBytes, 0u);
}

}  // namespace
}  // namespace rayes
