// Null-collision tracking through bricked media (shading/volume_tracking.h, shading/medium.h):
// delta tracking's free flights and ratio tracking's transmittance against closed forms, with
// tolerances of four standard errors of the estimators (binomial for delta tracking's escape
// fraction, the sample variance for ratio tracking), and the stiff cases.
#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include "shading/volume_tracking.h"

namespace rayes {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A medium whose voxel (x, y, z) in [0, 8·n)³ has density f(x, y, z), index space = world space
// (or `indexToWorld`), σ_a = 0, σ_s = sigma.
std::shared_ptr<Medium> makeMedium(int n, float sigma, const std::function<float(int, int, int)>& f,
                                   Transform indexToWorld = {}) {
  auto m = std::make_shared<Medium>(indexToWorld, MediumCoefficients{0, sigma, 0});
  for (int bx = 0; bx < n; ++bx)
    for (int by = 0; by < n; ++by)
      for (int bz = 0; bz < n; ++bz) {
        Medium::BrickVoxels v;
        for (int x = 0; x < 8; ++x)
          for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) v[size_t((x * 8 + y) * 8 + z)] = f(8 * bx + x, 8 * by + y, 8 * bz + z);
        m->addBrick({bx, by, bz}, v);
      }
  m->finish();
  return m;
}

struct Estimate {
  double mean, standardError;
};

// Delta tracking's escape fraction over `trials` paths (an unbiased estimate of T).
Estimate deltaTransmittance(const Medium& m, Vec3 o, Vec3 d, float tEnd, int trials, uint32_t seed = 1) {
  const std::shared_ptr<const Medium> list[] = {std::shared_ptr<const Medium>(&m, [](const Medium*) {})};
  int escaped = 0;
  TrackingCounts counts;
  for (int i = 0; i < trials; ++i) {
    TrackingRng rng{RngKey{uint32_t(i), 0, 1, seed}, kFreeFlightDimensions};
    escaped += sampleCollision(list, o, d, tEnd, rng, counts).medium < 0;
  }
  const double p = double(escaped) / trials;
  return {p, std::sqrt(std::max(p * (1 - p), 1.0 / trials) / trials)};
}

Estimate ratioEstimate(const Medium& m, Vec3 o, Vec3 d, float tEnd, int trials, uint32_t seed = 1) {
  const std::shared_ptr<const Medium> list[] = {std::shared_ptr<const Medium>(&m, [](const Medium*) {})};
  double sum = 0, sum2 = 0;
  TrackingCounts counts;
  for (int i = 0; i < trials; ++i) {
    TrackingRng rng{RngKey{uint32_t(i), 0, 1, seed}, kTransmittanceDimensions};
    const double T = ratioTransmittance(list, o, d, tEnd, rng, counts);
    EXPECT_TRUE(T >= 0 && T <= 1) << T;
    sum += T;
    sum2 += T * T;
  }
  const double mean = sum / trials, var = std::max(sum2 / trials - mean * mean, 1e-12);
  return {mean, std::sqrt(var / (trials - 1))};
}

// Within four standard errors (plus a float rounding allowance for exact cases).
void expectNear(const Estimate& e, double expected, const char* what) {
  EXPECT_NEAR(e.mean, expected, 4 * e.standardError + 1e-6) << what;
}

TEST(VolumeTracking, HomogeneousSlabTransmittanceIsExpOfMinusSigmaTimesDistance) {
  // 2·2·2 bricks of density 1: index [−½, 15.5)³. A ray along x through the middle crosses 16
  // units of constant density (trilinear interpolation of equal voxels, and the outermost half
  // voxel reads the same voxel row: every voxel of each brick's neighbourhood that exists is 1;
  // absent voxels beyond the slab read 0 only outside [0, 15], so use the inner segment).
  const auto m = makeMedium(2, 0.1f, [](int, int, int) { return 1.0f; });
  const Vec3 o{0, 7.3f, 8.1f}, d{1, 0, 0};
  const float dist = 15;  // [0, 15]: between the first and last voxel rows, density exactly 1
  const double exact = std::exp(-0.1 * dist);
  expectNear(deltaTransmittance(*m, o, d, dist, 20000), exact, "delta");
  expectNear(ratioEstimate(*m, o, d, dist, 20000), exact, "ratio");
  // A direction of length 2 halves the parameter range for the same world distance.
  expectNear(ratioEstimate(*m, o, d * 2.0f, dist / 2, 20000), exact, "ratio, |dir| = 2");
}

TEST(VolumeTracking, DensityGradientMatchesItsClosedFormOpticalDepth) {
  // ρ = x / 16 along x: trilinear interpolation reproduces a linear field exactly, so the optical
  // depth over [0, 15] is σ·(15² / 32).
  const auto m = makeMedium(2, 0.3f, [](int x, int, int) { return float(x) / 16; });
  const Vec3 o{0, 5.5f, 9.25f}, d{1, 0, 0};
  const double exact = std::exp(-0.3 * 15.0 * 15.0 / 32);
  const Estimate delta = deltaTransmittance(*m, o, d, 15, 20000), ratio = ratioEstimate(*m, o, d, 15, 20000);
  expectNear(delta, exact, "delta");
  expectNear(ratio, exact, "ratio");
  // Delta and ratio tracking agree with each other (independent estimators).
  EXPECT_NEAR(delta.mean, ratio.mean, 4 * std::hypot(delta.standardError, ratio.standardError));
}

TEST(VolumeTracking, ConstantDensitySphereWithinItsVoxelisationBound) {
  // Voxels inside a sphere of radius R = 12 about c = (16, 16, 16) have density 1. Trilinear
  // interpolation is exactly 1 where all 8 voxels around a point are inside (closer than
  // R − √3 to c) and 0 where all are outside (beyond R + √3), so the optical depth of a chord at
  // distance b from c lies between σ times the chords of those two spheres.
  const float R = 12, s = 0.15f;
  const Vec3 c{16, 16, 16};
  const auto m = makeMedium(4, s, [&](int x, int y, int z) {
    return length(Vec3{float(x), float(y), float(z)} - c) < R ? 1.0f : 0.0f;
  });
  for (const float b : {0.0f, 5.0f, 9.0f}) {
    const Vec3 o{-1, c.y + b, c.z};
    auto chord = [&](float r) { return r > b ? 2 * std::sqrt(r * r - b * b) : 0.0f; };
    const double hi = std::exp(-s * chord(R - std::sqrt(3.0f))), lo = std::exp(-s * chord(R + std::sqrt(3.0f)));
    const Estimate e = ratioEstimate(*m, o, {1, 0, 0}, 40, 20000);
    EXPECT_GE(e.mean, lo - 4 * e.standardError) << "b = " << b;
    EXPECT_LE(e.mean, hi + 4 * e.standardError) << "b = " << b;
  }
}

TEST(VolumeTracking, MajorantBoundsTheDensityEverywhereInItsCell) {
  // Random voxels: the density at random points of each brick's cell never exceeds its majorant.
  uint64_t state = 7;
  auto next = [&] { state = state * 6364136223846793005ull + 1442695040888963407ull; return float(state >> 40) * 0x1p-24f; };
  const auto m = makeMedium(2, 1, [&](int, int, int) { return next() * 3; });
  for (int b = 0; b < int(m->bricks()); ++b)
    for (int i = 0; i < 2000; ++i) {
      const int32_t cx = b / 4, cy = (b / 2) % 2, cz = b % 2;
      const int32_t brick = m->brickAt(cx, cy, cz);
      const Vec3 p{8 * cx - 0.5f + 8 * next(), 8 * cy - 0.5f + 8 * next(), 8 * cz - 0.5f + 8 * next()};
      ASSERT_LE(m->density(brick, p), m->majorant(brick));
    }
}

TEST(VolumeTracking, CameraInsideTheVolumeSeesOnlyTheRemainingDistance) {
  const auto m = makeMedium(2, 0.2f, [](int, int, int) { return 1.0f; });
  const Vec3 o{6, 7, 7}, d{1, 0, 0};  // 9 units of density 1 to x = 15
  const double exact = std::exp(-0.2 * 9);
  expectNear(deltaTransmittance(*m, o, d, 9, 20000), exact, "delta from inside");
  expectNear(ratioEstimate(*m, o, d, 9, 20000), exact, "ratio from inside");
}

TEST(VolumeTracking, RayGrazingABrickFaceStaysFiniteAndAgrees) {
  // Along the plane between two bricks (index y = 7.5) and along the grid's outer face (y = −½).
  const auto m = makeMedium(2, 0.1f, [](int, int, int) { return 1.0f; });
  for (const float y : {7.5f, -0.5f}) {
    const Vec3 o{-5, y, 8}, d{1, 0, 0};
    const Estimate delta = deltaTransmittance(*m, o, d, 30, 20000), ratio = ratioEstimate(*m, o, d, 30, 20000);
    EXPECT_TRUE(std::isfinite(delta.mean) && std::isfinite(ratio.mean));
    EXPECT_NEAR(delta.mean, ratio.mean, 4 * std::hypot(delta.standardError, ratio.standardError)) << "y = " << y;
  }
}

TEST(VolumeTracking, ZeroDensityCostsNoLookupAndTransmitsEverything) {
  const auto m = makeMedium(2, 1, [](int, int, int) { return 0.0f; });
  const std::shared_ptr<const Medium> list[] = {m};
  TrackingRng rng{RngKey{1, 2, 3, 4}, kFreeFlightDimensions};
  TrackingCounts counts;
  EXPECT_LT(sampleCollision(list, {-1, 3, 3}, {1, 0, 0}, kInf, rng, counts).medium, 0);
  EXPECT_EQ(ratioTransmittance(list, {-1, 3, 3}, {1, 0, 0}, kInf, rng, counts), 1.0f);
  EXPECT_EQ(counts.lookups, 0u);
}

TEST(VolumeTracking, VeryDenseBrickStopsAtOnceInBoundedWork) {
  // Density 10⁶ per unit: a ray entering collides within a hair of the entry, and ratio tracking
  // returns 0 after one lookup (the interior density equals its majorant) -- not 10⁶ steps.
  const auto m = makeMedium(1, 1, [](int, int, int) { return 1e6f; });
  const std::shared_ptr<const Medium> list[] = {m};
  for (uint32_t i = 0; i < 100; ++i) {
    TrackingRng rng{RngKey{i, 0, 1, 0}, kFreeFlightDimensions};
    TrackingCounts counts;
    const Collision c = sampleCollision(list, {3, 3, 3}, {1, 0, 0}, kInf, rng, counts);
    ASSERT_EQ(c.medium, 0);
    EXPECT_LT(c.t, 1e-4f);
    EXPECT_EQ(ratioTransmittance(list, {3, 3, 3}, {1, 0, 0}, kInf, rng, counts), 0.0f);
    EXPECT_LT(counts.lookups, 50u);
  }
}

TEST(VolumeTracking, OneVoxelBrickHasThatVoxelAsMajorantAndTheEstimatorsAgree) {
  auto m = std::make_shared<Medium>(Transform{}, MediumCoefficients{0, 2, 0});
  Medium::BrickVoxels v{};
  v[size_t((3 * 8 + 3) * 8 + 3)] = 1.5f;
  m->addBrick({0, 0, 0}, v);
  m->finish();
  EXPECT_EQ(m->bricks(), 1u);
  EXPECT_EQ(m->majorant(0), 1.5f);
  // Through the voxel: a tent of height 1.5 and width 2 along x, optical depth 2·1.5 = 3.
  const Vec3 o{-1, 3, 3}, d{1, 0, 0};
  const double exact = std::exp(-3.0);
  const Estimate delta = deltaTransmittance(*m, o, d, 20, 20000), ratio = ratioEstimate(*m, o, d, 20, 20000);
  expectNear(delta, exact, "delta");
  expectNear(ratio, exact, "ratio");
}

TEST(VolumeTracking, TransformedMediumCountsWorldDistance) {
  // Index voxels of world size 0.5, moved by (10, 0, 0): the slab's 15 index units are 7.5
  // world units, and σ is per world unit.
  Transform xf = Transform::translate({10, 0, 0}) * Transform::scale({0.5f, 0.5f, 0.5f});
  const auto m = makeMedium(2, 0.2f, [](int, int, int) { return 1.0f; }, xf);
  const double exact = std::exp(-0.2 * 7.5);
  expectNear(ratioEstimate(*m, {10, 3.5f, 4}, {1, 0, 0}, 7.5f, 20000), exact, "scaled");
}

TEST(VolumeTracking, SameKeySameCollisionBits) {
  const auto m = makeMedium(2, 0.1f, [](int x, int y, int z) { return float((x * 7 + y * 3 + z) % 5); });
  const std::shared_ptr<const Medium> list[] = {m};
  for (uint32_t i = 0; i < 50; ++i) {
    TrackingRng a{RngKey{i, 3, 2, 9}, kFreeFlightDimensions}, b = a;
    TrackingCounts counts;
    const Collision ca = sampleCollision(list, {-1, 4, 5}, {1, 0.1f, 0}, kInf, a, counts);
    const Collision cb = sampleCollision(list, {-1, 4, 5}, {1, 0.1f, 0}, kInf, b, counts);
    EXPECT_EQ(ca.t, cb.t);
    EXPECT_EQ(ca.medium, cb.medium);
  }
}

// The sorted engine's brick leaves call brickCollision and brickTransmittance once per brick a
// ray crosses, in whatever order the sort gives; the walk of one ray calls them along the ray.
// With per-brick streams both are the same bits: the minimum of the collisions and the
// TransmittanceProduct of the factors do not depend on the order. Two overlapping media, one
// transformed, and rays from every side (some starting inside).
TEST(VolumeTracking, BrickByBrickInAnyOrderGivesTheWalksBits) {
  const auto a = makeMedium(3, 0.3f, [](int x, int y, int z) { return float((x * 7 + y * 3 + z * 5) % 11) / 4; });
  const auto b = makeMedium(2, 0.5f, [](int x, int y, int z) { return float((x + 2 * y + 3 * z) % 4); },
                            Transform::translate({5, 3, 2}) * Transform::scale({0.75f, 0.75f, 0.75f}));
  const std::shared_ptr<const Medium> list[] = {a, b};
  const BrickNumbering numbering(list);
  ASSERT_EQ(numbering.total(), 27u + 8u);
  int collided = 0, partial = 0;
  for (uint32_t i = 0; i < 400; ++i) {
    const RngKey key{i, 1, 2, 3};
    const Vec3 o{sampleUniform(key, 0) * 30 - 3, sampleUniform(key, 1) * 30 - 3, sampleUniform(key, 2) * 30 - 3};
    const Vec3 target{sampleUniform(key, 3) * 24, sampleUniform(key, 4) * 24, sampleUniform(key, 5) * 24};
    const Vec3 d = (target - o) * 0.37f;  // not unit: t counts in units of |d|
    const float tEnd = i % 3 == 0 ? kInf : 2.5f;
    TrackingCounts counts;
    TrackingRng flight{key, kFreeFlightDimensions}, shadow{key, kTransmittanceDimensions};
    const Collision walked = sampleCollision(list, o, d, tEnd, flight, counts);
    const float T = walkTransmittance(list, o, d, tEnd, false, shadow, counts);
    // Every brick of both media, last first.
    Collision byBrick;
    uint64_t product = 0;
    for (uint32_t g = numbering.total(); g-- > 0;) {
      const BrickNumbering::Brick at = numbering.brickOf(g);
      const Medium& m = *list[at.medium];
      const IndexRay r = toIndex(m, o, d);
      GridReader reader(m.densityGrid(), nullptr);
      const float t = brickCollision(m, at.brick, r, tEnd, brickStream(key, kFreeFlightDimensions, g), counts, reader);
      if (t < byBrick.t) byBrick = {t, int32_t(at.medium)};
      TransmittanceProduct::addLocal(product, TransmittanceProduct::term(brickTransmittance(
                                                  m, at.brick, r, tEnd, false,
                                                  brickStream(key, kTransmittanceDimensions, g), counts, reader)));
    }
    EXPECT_EQ(walked.t, byBrick.t) << "ray " << i;
    EXPECT_EQ(walked.medium, byBrick.medium) << "ray " << i;
    EXPECT_EQ(T, TransmittanceProduct::valueOf(product)) << "ray " << i;
    collided += walked.medium >= 0;
    partial += T > 0 && T < 1;
  }
  // The rays did meet the media: both outcomes occur.
  EXPECT_GT(collided, 40);
  EXPECT_GT(partial, 40);
}

// The top level's brick leaves: one per brick by default (leaf l is brick l), or the bricks of
// each 2 × 2 × 2 block of cells of one medium; either way every brick is in exactly one leaf, of
// its own medium, in leaf order by first brick.
TEST(VolumeTracking, BrickLeavesPartitionEachMediumsBricksIntoBlocksOfCells) {
  const auto a = makeMedium(3, 1, [](int, int, int) { return 1.0f; });
  const auto b = makeMedium(2, 1, [](int, int, int) { return 1.0f; }, Transform::translate({40, 0, 0}));
  const std::shared_ptr<const Medium> list[] = {a, b};
  const BrickNumbering single(list, 1);
  ASSERT_EQ(single.leaves(), single.total());
  for (uint32_t l = 0; l < single.leaves(); ++l) {
    ASSERT_EQ(single.bricksOfLeaf(l).size(), 1u);
    EXPECT_EQ(single.bricksOfLeaf(l)[0], l);
    EXPECT_EQ(single.mediumOfLeaf(l), single.brickOf(l).medium);
  }
  const BrickNumbering grouped(list, 2);
  // Medium a's 3³ cells fall in 2³ blocks (sizes 8, 4, 4, 4, 2, 2, 2, 1), medium b's 2³ in one.
  ASSERT_EQ(grouped.leaves(), 8u + 1u);
  std::vector<int> leafOf(grouped.total(), -1);
  for (uint32_t l = 0; l < grouped.leaves(); ++l)
    for (const uint32_t g : grouped.bricksOfLeaf(l)) {
      EXPECT_EQ(leafOf[g], -1) << "brick " << g << " in two leaves";
      leafOf[g] = int(l);
      const BrickNumbering::Brick at = grouped.brickOf(g);
      EXPECT_EQ(grouped.mediumOfLeaf(l), at.medium);
      const BrickCoord c = list[at.medium]->densityGrid().coord(at.brick);
      const BrickCoord first = list[at.medium]->densityGrid().coord(grouped.brickOf(grouped.bricksOfLeaf(l)[0]).brick);
      EXPECT_EQ(c.x / 2, first.x / 2);
      EXPECT_EQ(c.y / 2, first.y / 2);
      EXPECT_EQ(c.z / 2, first.z / 2);
    }
  for (uint32_t g = 0; g < grouped.total(); ++g) EXPECT_GE(leafOf[g], 0) << "brick " << g << " in no leaf";
  EXPECT_EQ(grouped.bricksOfLeaf(0).size(), 8u);
  EXPECT_EQ(grouped.bricksOfLeaf(8).size(), 8u);
}

// A brick's world box (its top-level leaf) holds its cell: the segment the tracking clips to
// lies inside the box's slab interval for any ray.
TEST(VolumeTracking, BrickWorldBoundsHoldTheCellsSegment) {
  const auto m = makeMedium(2, 1, [](int, int, int) { return 1.0f; },
                            Transform::translate({1e3f, -7, 2}) * Transform::rotate({1, 2, 3}, 40.0f) *
                                Transform::scale({0.3f, 0.5f, 0.2f}));
  for (uint32_t i = 0; i < 200; ++i) {
    const RngKey key{i, 0, 0, 5};
    const int32_t brick = int32_t(i % m->bricks());
    const Box3 box = m->brickWorldBounds(brick);
    const Vec3 c = box.center();
    const Vec3 o = c + Vec3{sampleUniform(key, 0) - 0.5f, sampleUniform(key, 1) - 0.5f, sampleUniform(key, 2) - 0.5f} * 20;
    const Vec3 d = c + Vec3{sampleUniform(key, 3) - 0.5f, sampleUniform(key, 4) - 0.5f, sampleUniform(key, 5) - 0.5f} * 4 - o;
    float t0, t1;
    if (!brickSegment(*m, brick, toIndex(*m, o, d), kInf, t0, t1)) continue;
    for (const float t : {t0, t1, 0.5f * (t0 + t1)}) {
      const Vec3 p = o + d * t;
      EXPECT_TRUE(p.x >= box.lo.x && p.y >= box.lo.y && p.z >= box.lo.z && p.x <= box.hi.x && p.y <= box.hi.y &&
                  p.z <= box.hi.z)
          << "ray " << i;
    }
  }
}

TEST(HenyeyGreenstein, IsNormalisedAndSamplesItsMeanCosine) {
  for (const float g : {-0.7f, 0.0f, 0.5f, 0.9f}) {
    // ∫ p dω = 2π ∫ p(µ) dµ by the midpoint rule (error far below the tolerance for |g| ≤ 0.9).
    double integral = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) integral += henyeyGreenstein(-1 + (i + 0.5) * 2.0 / n, g) * (2.0 / n);
    EXPECT_NEAR(2 * M_PI * integral, 1.0, 1e-3) << "g = " << g;
    // E[cos] = g; the variance of cos is at most 1, so SE ≤ 1/√N.
    const int N = 40000;
    double sum = 0;
    const Vec3 in = normalize(Vec3{0.3f, -0.5f, 0.8f});
    for (int i = 0; i < N; ++i) {
      const Vec3 w = sampleHenyeyGreenstein(in, g, sampleUniform({uint32_t(i), 0, 0, 5}, 0),
                                            sampleUniform({uint32_t(i), 0, 0, 5}, 1));
      ASSERT_NEAR(length(w), 1.0f, 1e-5f);
      sum += dot(in, w);
    }
    EXPECT_NEAR(sum / N, g, 4 / std::sqrt(double(N))) << "g = " << g;
  }
}

}  // namespace
}  // namespace rayes
