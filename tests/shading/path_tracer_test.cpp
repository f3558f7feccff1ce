// The path-tracer kernels at their edges: secondary-ray offsets stay finite and scale with the
// geometry, and a non-finite hit never reaches the film (docs/design.md, invariant 5).
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <gtest/gtest.h>
#include "core/box.h"
#include "shading/path_tracer.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// The offset is the dicing-error bound at the ray's level plus gamma(32) of the coordinates'
// magnitude and the patch's extent (path_tracer.cpp derives it): these check that formula at
// its edges, where it must stay finite, positive and no larger than the bound it claims.
constexpr float kRounding = gammaBound(32);

float roundingOf(Vec3 p, Vec3 from, float side) {
  return kRounding * (maxComponent(vabs(p)) + maxComponent(vabs(from)) + side);
}

TEST(OriginOffset, DicingErrorOfTheLevelPlusRounding) {
  // A curved patch: C / 4^m dominates, exactly 4x smaller per level.
  EXPECT_FLOAT_EQ(originOffset(1.0f, 0.5f, 0, {0, 0, 0}, {0, 0, 0}), 0.5f + kRounding);
  EXPECT_FLOAT_EQ(originOffset(1.0f, 0.5f, 3, {0, 0, 0}, {0, 0, 0}), 0.5f / 64 + kRounding);
  // Level 10: 4^-10 of C.
  const float fine = originOffset(1.0f, 0.5f, 10, {1, 1, 1}, {0, 0, 5});
  EXPECT_FLOAT_EQ(fine, 0.5f / 1048576 + roundingOf({1, 1, 1}, {0, 0, 5}, 1));
  // A planar patch: rounding alone, whatever the level.
  for (int level : {0, 10})
    EXPECT_FLOAT_EQ(originOffset(2.0f, 0.0f, level, {3, 0, 0}, {0, 0, 0}), roundingOf({3, 0, 0}, {}, 2));
}

TEST(OriginOffset, RoundingScalesWithCoordinatesAndExtent) {
  // Far from the origin: several ulps of the coordinates (the spacing at 1e6 is 0.0625), and
  // no more than the bound.
  const float far = originOffset(1.0f, 0.0f, 4, {1e6f, 0, 0}, {1e6f, 0, 10});
  EXPECT_GT(far, 8 * 0.0625f);
  EXPECT_LE(far, roundingOf({1e6f, 0, 0}, {1e6f, 0, 10}, 1) * (1 + 1e-6f));
  // Huge and tiny patches: proportional to their size.
  EXPECT_FLOAT_EQ(originOffset(1e30f, 0.0f, 0, {0, 0, 0}, {0, 0, 0}), kRounding * 1e30f);
  const float tiny = originOffset(1e-20f, 0.0f, 0, {0, 0, 0}, {0, 0, 0});
  EXPECT_GT(tiny, 0.0f);
  EXPECT_LE(tiny, kRounding * 1e-20f * (1 + 1e-6f));
  // A zero-size patch at the origin: still positive (the smallest normal float), never zero.
  const float zero = originOffset(0.0f, 0.0f, 0, {0, 0, 0}, {0, 0, 0});
  EXPECT_GT(zero, 0.0f);
  EXPECT_LE(zero, 2 * std::numeric_limits<float>::min());
}

TEST(OriginOffset, FiniteAndPositiveForExtremeInputs) {
  const float big = 3e38f;
  for (float c : {0.0f, 1.0f, big, kInf, NAN})
    for (int level : {0, 10, 40})
      for (Vec3 p : {Vec3{0, 0, 0}, Vec3{big, big, big}, Vec3{-1e6f, 2, 3}}) {
        const float o = originOffset(big, c, level, p, p);
        EXPECT_TRUE(std::isfinite(o)) << c << " " << level;
        EXPECT_GT(o, 0.0f) << c << " " << level;
      }
}

struct OneLightScene {
  ShadingScene scene;
  OneLightScene() {
    scene.camera = PerspectiveCamera({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 2, 2);
    scene.width = scene.height = 2;
    scene.integrator.maxDepth = 4;
    Material m;
    m.albedo = Rgb{0.5f, 0.5f, 0.5f};
    scene.materials = {m};
    scene.leafMaterial = {0};
    scene.leafSide = {2};
    scene.leafDicingError = {0};
    scene.lights = LightSampler({{{0, 0, 3}, {10, 10, 10}}}, {});
  }
};

// The batch keeps a path's first hit packed; the film must get what shading saw, bit for bit.
TEST(FirstHitRecord, UnpacksToTheFirstHitShadingSaw) {
  EXPECT_FALSE(FirstHitRecord{}.unpack().hitSurface);
  EXPECT_EQ(FirstHitRecord{}.unpack().materialId, -1);
  RayHit h;
  h.setNormals({0, 0, 1}, normalize(Vec3{0.3f, -0.4f, 0.5f}));
  for (const bool flipped : {false, true}) {
    FirstHitRecord r;
    r.flags = FirstHitRecord::kHitSurface | (flipped ? FirstHitRecord::kNormalFlipped : 0);
    r.depth = 7.25f;
    r.normalCode = h.nsCode;
    r.lod = 11;
    r.albedo = {0.1f, 0.2f, 0.3f};
    r.materialId = 4;
    const FirstHit f = r.unpack();
    EXPECT_TRUE(f.hitSurface);
    EXPECT_EQ(f.depth, 7.25f);
    EXPECT_EQ(f.normal, flipped ? -h.ns() : h.ns());
    EXPECT_EQ(f.lod, 11.0f);
    EXPECT_EQ(f.albedo.y, 0.2f);
    EXPECT_EQ(f.materialId, 4);
  }
}

TEST(PathTracerKernels, NonFiniteHitIsDroppedAndCounted) {
  OneLightScene s;
  PathTracer tracer(s.scene);
  PathBatch paths;
  RayBatch rays;
  tracer.start(0, 4, paths, rays);
  for (int k = 0; k < 4; ++k) {
    RayHit& h = rays.hit[2 * k];
    h.leaf = 0;
    h.t = 5;
    h.setNormals({0, 0, 1}, {0, 0, 1});
  }
  // A broken shading normal cannot reach shading: the hit record stores it as +z.
  rays.hit[0].setNormals({0, 0, 1}, {NAN, 0, 1});
  EXPECT_TRUE(isFinite(rays.hit[0].ns()));
  rays.hit[2].t = kInf;          // hit at infinity: p is not finite
  ShadeStats stats;
  tracer.shade(0, paths, rays, stats);
  EXPECT_GE(stats.nonFinite.load(), 1u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_TRUE(isFinite(paths.radiance[k])) << k;
    EXPECT_TRUE(isFinite(paths.throughput[k])) << k;
    EXPECT_TRUE(isFinite(paths.shadowContribution[k])) << k;
  }
  // The healthy paths were shaded: they sent a shadow ray toward the light.
  EXPECT_EQ(rays.ray[2 * 3 + 1].kind, RayKind::Shadow);
  paths.radiance[1] = {kInf, 0, 0};  // an overflowed sum
  const uint64_t before = stats.nonFinite.load();
  Film film(2, 2);
  tracer.finish(paths, film, stats);
  EXPECT_EQ(stats.nonFinite.load(), before + 1);
  for (float v : film.beautyRgba()) EXPECT_TRUE(std::isfinite(v));
}

// The shading sort's items live in the batch's sort scratch (RayBatch::sortScratch), which the
// engine's candidate sort used while the batch was traced: the path tracer asks for
// sortScratchBytesPerPath() per path of it, keeps no sort memory of its own (bytesPerPath()
// does not count it), and uses a scratch the trace left large enough where it lies.
TEST(PathTracerKernels, TheShadingSortTakesItsItemsFromTheBatchsScratch) {
  OneLightScene s;
  PathTracer tracer(s.scene);
  EXPECT_EQ(tracer.sortScratchBytesPerPath(), 2 * sizeof(uint32_t));  // a rank and a path id
  EXPECT_EQ(tracer.bytesPerPath(), PathBatch::bytesPerPath());
  for (const bool lentEnough : {false, true}) {
    PathBatch paths;
    RayBatch rays;
    tracer.start(0, 4, paths, rays);
    const void* lent = lentEnough ? rays.sortScratch.take<uint32_t>(100).data() : nullptr;
    for (int k = 0; k < 4; ++k) {
      RayHit& h = rays.hit[2 * k];
      h.leaf = 0;
      h.t = 5 / length(rays.ray[2 * k].dir());
      h.setNormals({0, 0, 1}, {0, 0, 1});
    }
    ShadeStats stats;
    tracer.shade(0, paths, rays, stats);
    EXPECT_EQ(stats.shadedHits.load(), 4u);
    if (lentEnough) {
      EXPECT_EQ(rays.sortScratch.bytes(), 400u);
      EXPECT_EQ(static_cast<const void*>(rays.sortScratch.take<uint32_t>(1).data()), lent);
    } else {
      EXPECT_EQ(rays.sortScratch.bytes(), 4 * tracer.sortScratchBytesPerPath());
    }
  }
}

// The first hits reach the film right after the camera generation (addFirstHits), not with the
// radiance: each path's exactly once from `from` on, what shading saw (depth, material), with the
// film's radiance untouched until finish(); the slots they were kept in are left cleared, so the
// next generation reads no stale hit. 2x2 pixels, 1 sample: path k is pixel k.
TEST(PathTracerKernels, FirstHitsReachTheFilmOnceAfterTheCameraGeneration) {
  OneLightScene s;
  PathTracer tracer(s.scene);
  PathBatch paths;
  RayBatch rays;
  rays.shadowPairs = true;
  tracer.start(0, 4, paths, rays);
  for (int k = 0; k < 4; ++k) {
    RayHit& h = rays.hitOf(2 * size_t(k));
    h.leaf = k == 3 ? kNoLeaf : 0;  // path 3 sees nothing
    h.t = 5.0f + float(k);
    h.setNormals({0, 0, 1}, {0, 0, 1});
  }
  ShadeStats stats;
  tracer.shade(0, paths, rays, stats);
  Film film(2, 2);
  tracer.addFirstHits(paths, rays, film, 1);  // path 0's first hit is in the film already
  const Film::Sums& f = film.sums();
  EXPECT_EQ(f.hits, (std::vector<uint32_t>{0, 1, 1, 0}));
  EXPECT_EQ(f.depth[1], 6.0);
  EXPECT_EQ(f.depth[2], 7.0);
  EXPECT_EQ(f.material[1], 0);
  EXPECT_EQ(f.material[3], -1);
  EXPECT_EQ(f.count, (std::vector<uint32_t>{0, 0, 0, 0}));  // the radiance comes with finish()
  for (int k = 0; k < 4; ++k) EXPECT_FALSE(rays.hitOf(2 * size_t(k)).valid()) << k;
  tracer.finish(paths, film, stats);
  EXPECT_EQ(f.count, (std::vector<uint32_t>{1, 1, 1, 1}));
  EXPECT_EQ(f.hits, (std::vector<uint32_t>{0, 1, 1, 0}));
}

// Next-event shadow rays test the segment from the offset origin to the light point, which is
// itself moved off the emitter toward the receiver: they end in front of the light, never past
// it (where a ceiling just behind the light would block them), however large the receiver's
// offset is.
TEST(PathTracerKernels, ShadowRayEndsInFrontOfTheLightPoint) {
  OneLightScene s;
  const float lightZ = 3;
  PatchLight rect;
  rect.evaluate = [&](float u, float v, Vec3& p, Vec3& n) {
    p = {2 * u - 1, 2 * v - 1, lightZ};
    n = {0, 0, -4};  // dP/du x dP/dv, facing the receiver below
  };
  rect.radiance = {1, 1, 1};
  rect.leaf = 1;
  s.scene.lights = LightSampler({}, {rect});
  s.scene.leafMaterial = {0, 0};
  s.scene.leafSide = {2, 2};
  s.scene.leafDicingError = {0.5f, 0};  // a receiver with a large offset at level 0
  PathTracer tracer(s.scene);
  PathBatch paths;
  RayBatch rays;
  tracer.start(0, 4, paths, rays);
  for (int k = 0; k < 4; ++k) {
    RayHit& h = rays.hit[2 * k];
    h.leaf = 0;
    h.level = 0;
    h.t = 5 / length(rays.ray[2 * k].dir());  // 5 from the camera: below the light
    h.setNormals({0, 0, 1}, {0, 0, 1});
  }
  ShadeStats stats;
  tracer.shade(0, paths, rays, stats);
  int shadowRays = 0;
  for (int k = 0; k < 4; ++k) {
    const size_t ss = 2 * size_t(k) + 1;
    if (rays.ray[ss].kind != RayKind::Shadow) continue;
    ++shadowRays;
    const Vec3 end = rays.ray[ss].org + rays.ray[ss].dir() * rays.ray[ss].tmax;
    EXPECT_LT(end.z, lightZ) << k;
    EXPECT_GT(end.z, lightZ - 1e-3f) << k;  // and not short of it by more than the offsets
    EXPECT_EQ(rays.ray[ss].ignoreLeaf, 1u) << k;
  }
  EXPECT_GT(shadowRays, 0);
}

// Path ids by pixel blocks (PathTracer::setPixelBlock): for every block size, ids [0, pixels·spp)
// name every (pixel, sample) exactly once; a block's ids are its pixels' with all their samples,
// sample-major within it; and n = 0 or n = pixels is the sample-major order sample·pixels + pixel.
// The blocks here do not divide the image (7x5 pixels, 3 samples), so the last one is short.
TEST(PathIds, EveryBlockSizeNamesEveryPixelAndSampleOnceAndKeepsABlocksPixelsTogether) {
  ShadingScene scene;
  scene.width = 7;
  scene.height = 5;
  scene.samplesPerPixel = 3;
  const uint64_t pixels = 35, spp = 3;
  PathTracer tracer(scene);
  for (const uint32_t n : {0u, 1u, 4u, 6u, 34u, 35u}) {
    tracer.setPixelBlock(n);
    std::set<std::pair<uint32_t, uint32_t>> seen;
    std::map<uint32_t, uint32_t> lastSample;
    const uint64_t block = n == 0 ? pixels : n;
    for (uint64_t id = 0; id < pixels * spp; ++id) {
      const PathTracer::PathIds ids = tracer.idsOf(id);
      ASSERT_LT(ids.pixel, pixels);
      ASSERT_LT(ids.sample, spp);
      EXPECT_TRUE(seen.insert({ids.pixel, ids.sample}).second) << "block " << n << ", id " << id;
      // The block of the id is the block of its pixel.
      EXPECT_EQ(id / (block * spp), ids.pixel / block) << "block " << n << ", id " << id;
      if (n == 0 || n == pixels) {
        EXPECT_EQ(ids.pixel, id % pixels);
        EXPECT_EQ(ids.sample, id / pixels);
      }
      // A pixel's samples come in increasing id order (the film adds them so).
      if (auto it = lastSample.find(ids.pixel); it != lastSample.end()) {
        EXPECT_GT(ids.sample, it->second) << "block " << n << ", id " << id;
      }
      lastSample[ids.pixel] = ids.sample;
    }
    EXPECT_EQ(seen.size(), pixels * spp);
  }
}

}  // namespace
}  // namespace rayes
