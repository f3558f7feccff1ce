// The surface derivatives every engine keeps at a closest hit (RayBatch::dpd, when the batch asks
// for them): the hit micro-quad's bilinear partials times 2^level, which are the patch's own
// dP/du, dP/dv to within what the quad's size allows. On a bilinear patch the micro-quad *is*
// the patch over its square, so only rounding separates them; on a Bézier patch the difference
// quotient over a quad of side h = 2^-level is within h (max|P_uu| + max|P_uv|) of P_u anywhere in
// the quad (and likewise for v). Both walks of the SortedEngine and the CachingEngine keep the
// same bits; a batch that does not ask keeps none.
#include <cmath>
#include <cstring>
#include <limits>
#include <gtest/gtest.h>
#include "core/rng.h"
#include "geometry/bezier_patch.h"
#include "geometry/bilinear_patch.h"
#include "geometry/moving_patch.h"
#include "rays/caching_engine.h"
#include "rays/embree_engine.h"
#include "rays/sorted_engine.h"
#include "rays/teapot_on_floor.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kLod = 4;

// The teapot on its floor and, behind, a skewed, non-planar bilinear wall: partials that vary
// over the patch.
struct World : test::TracedWorld {
  World()
      : TracedWorld(test::teapotOnFloorAnd(
            {std::make_shared<BilinearPatch>(Vec3{-5, 5, 0}, Vec3{5, 6, 1}, Vec3{-4, 5, 6}, Vec3{5, 4, 7})})) {}
};

RayBatch randomRays(int n, bool derivatives) {
  RayBatch b;
  b.derivatives = derivatives;
  b.resize(n);
  for (int i = 0; i < n; ++i) {
    const RngKey k{uint32_t(i), 0, 0, 31};
    const float a = 6.2831853f * sampleUniform(k, 0);
    const Vec3 o{7 * std::cos(a), 7 * std::sin(a), 0.5f + 5 * sampleUniform(k, 1)};
    const Vec3 to{-3 + 6 * sampleUniform(k, 2), -3 + 9 * sampleUniform(k, 3), 4 * sampleUniform(k, 4)};
    b.setFromNowhere(i, RayKind::Closest, o, normalize(to - o), kInf, 0.0f, 0.0f);
  }
  return b;
}

// The patch's analytic first and (for the bound) second derivatives at (u, v).
SurfaceDerivatives analytic(const Patch& p, float u, float v) {
  if (const auto* b = dynamic_cast<const BilinearPatch*>(&p)) return b->derivatives(u, v);
  const auto& z = dynamic_cast<const BezierPatch&>(p);
  return BezierPatch::derivativesOnRow(z.rowAt(v), u);
}

// max|P_uu| + max|P_uv| and max|P_vv| + max|P_uv| over the patch, sampled on a grid 16 times
// finer than the quads (the second derivatives of a bicubic vary smoothly: the samples' maximum
// is doubled to cover what lies between them).
void secondDerivativeBounds(const Patch& p, double& boundU, double& boundV) {
  double uu = 0, uv = 0, vv = 0;
  const int n = 16 << kLod;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const SurfaceDerivatives d = analytic(p, float(i) / n, float(j) / n);
      uu = std::max(uu, double(length(d.puu)));
      uv = std::max(uv, double(length(d.puv)));
      vv = std::max(vv, double(length(d.pvv)));
    }
  boundU = 2 * (uu + uv);
  boundV = 2 * (vv + uv);
}

// Every hit's derivatives against the patch's, within h (second-derivative bound) plus the
// rounding of the vertex differences (a few ulps of the vertices' magnitude, times 2^level).
void expectAnalyticDerivatives(const World& w, const RayBatch& b, int minHits) {
  const double h = std::ldexp(1.0, -kLod);
  std::vector<double> boundU(w.leaves.size(), -1), boundV(w.leaves.size(), -1);
  int hits = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    const RayHit& hit = b.hit[i];
    if (!hit.valid()) continue;
    ++hits;
    const Patch& p = *w.leaves[hit.leaf];
    if (boundU[hit.leaf] < 0) secondDerivativeBounds(p, boundU[hit.leaf], boundV[hit.leaf]);
    const SurfaceDerivatives ref = analytic(p, hit.u, hit.v);
    const HitDerivatives& got = b.dpd[i];
    ASSERT_TRUE(isFinite(got.dpdu) && isFinite(got.dpdv)) << "ray " << i;
    const double magnitude = maxComponent(vmax(vabs(p.bounds().lo), vabs(p.bounds().hi)));
    const double rounding = 8 * 0x1p-24 * magnitude / h;
    EXPECT_LE(length(got.dpdu - ref.pu), h * boundU[hit.leaf] + rounding) << "ray " << i << " leaf " << hit.leaf;
    EXPECT_LE(length(got.dpdv - ref.pv), h * boundV[hit.leaf] + rounding) << "ray " << i << " leaf " << hit.leaf;
  }
  EXPECT_GT(hits, minHits);
}

void traceSorted(const World& w, RayBatch& b, bool sorted) {
  TraceSettings s;
  s.maxLod = kLod;
  s.sortByLeaf = sorted;
  SortedEngine engine(w.top, w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
}

TEST(HitDerivatives, SortedPipelineGivesThePatchsPartialsWithinTheQuadBound) {
  World w;
  RayBatch b = randomRays(3000, true);
  traceSorted(w, b, true);
  expectAnalyticDerivatives(w, b, 1500);
}

TEST(HitDerivatives, BothWalksOfTheSortedEngineAndTheCachingEngineKeepTheSameBits) {
  World w;
  RayBatch sorted = randomRays(3000, true), alone = randomRays(3000, true), cached = randomRays(3000, true);
  traceSorted(w, sorted, true);
  traceSorted(w, alone, false);
  TraceSettings s;
  s.maxLod = kLod;
  CachingEngine caching(w.top, w.source, s, 4);
  GenerationStats stats;
  TraceTimes times;
  caching.trace(cached, stats, times);
  for (size_t i = 0; i < sorted.size(); ++i) {
    ASSERT_EQ(sorted.hit[i].leaf, alone.hit[i].leaf);
    ASSERT_EQ(sorted.hit[i].leaf, cached.hit[i].leaf);
    for (const RayBatch* other : {&alone, &cached}) {
      ASSERT_EQ(std::memcmp(&sorted.dpd[i], &other->dpd[i], sizeof(HitDerivatives)), 0) << "ray " << i;
    }
  }
}

TEST(HitDerivatives, EmbreeEngineGivesThePatchsPartialsWithinTheQuadBound) {
  World w;
  RayBatch b = randomRays(3000, true);
  EmbreeSettings s;
  s.maxLod = kLod;
  EmbreeEngine engine(w.source, s);
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
  expectAnalyticDerivatives(w, b, 1500);
}

TEST(HitDerivatives, ABatchThatDoesNotAskKeepsNone) {
  World w;
  RayBatch b = randomRays(100, false);
  traceSorted(w, b, true);
  EXPECT_TRUE(b.dpd.empty());
  EXPECT_EQ(b.derivativesOf(0), nullptr);
  EXPECT_EQ(RayBatch::bytesPerRay(false, true) - RayBatch::bytesPerRay(false, false), sizeof(HitDerivatives));
}

// A moving patch (translated between its time samples) has at every time the static patch's
// partials: the blended grid's quads are translated copies.
TEST(HitDerivatives, AMovingGridGivesTheBlendedQuadsPartials) {
  const Vec3 p00{-2, -2, 1}, p10{2, -2, 1.5f}, p01{-2, 2, 2}, p11{2, 2, 1};
  std::vector<PatchPtr> samples;
  for (const Vec3 shift : {Vec3{0, 0, 0}, Vec3{0.5f, 0, 0}})
    samples.push_back(std::make_shared<BilinearPatch>(p00 + shift, p10 + shift, p01 + shift, p11 + shift));
  std::vector<PatchPtr> leaves{std::make_shared<MovingPatch>(samples, std::vector<float>{0.0f, 1.0f})};
  StoredLeaves source(leaves);
  TopLevelBvh top;
  const std::vector<Box3> boxes{leaves[0]->bounds()};
  top.build(boxes);
  TraceSettings s;
  s.maxLod = kLod;
  SortedEngine engine(top, source, s);
  RayBatch b;
  b.derivatives = true;
  b.resize(200);
  for (int i = 0; i < 200; ++i) {
    const RngKey k{uint32_t(i), 0, 0, 7};
    const Vec3 to{-1.5f + 3 * sampleUniform(k, 0), -1.5f + 3 * sampleUniform(k, 1), 1.5f};
    b.set(i, RayKind::Closest, Vec3{0, 0, 10}, normalize(to - Vec3{0, 0, 10}), kInf, 0, 0, kNoLeaf, kNoLeaf, 0,
          sampleUniform(k, 2));
  }
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b, stats, times);
  const BilinearPatch still(p00, p10, p01, p11);
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    if (!b.hit[i].valid()) continue;
    ++hits;
    const SurfaceDerivatives ref = still.derivatives(b.hit[i].u, b.hit[i].v);
    // Rounding only: vertices of magnitude <= 3, differences times 2^level.
    const double bound = 8 * 0x1p-24 * 3 * 16;
    EXPECT_LE(length(b.dpd[i].dpdu - ref.pu), bound) << i;
    EXPECT_LE(length(b.dpd[i].dpdv - ref.pv), bound) << i;
  }
  EXPECT_GT(hits, 150);
}

}  // namespace
}  // namespace rayes
