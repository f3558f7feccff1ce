// The compact per-ray record: the hit keeps its normals as octahedral codes (28 bytes), and a
// batch keeps a shutter time per ray only when asked to. The bound is the encoding's: two
// 16-bit snorm coordinates on the octahedron, at most 1e-4 rad from the exact normal.
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/octahedral.h"
#include "core/ray_batch.h"
#include "core/rng.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

bool unitAndFinite(Vec3 d) { return isFinite(d) && std::fabs(length(d) - 1.0f) < 1e-6f; }

TEST(RayHit, IsTwentyEightBytesAndDecodesANormalWithinTheEncodingBound) {
  EXPECT_EQ(sizeof(RayHit), 28u);
  RayHit h;
  EXPECT_FALSE(h.valid());
  EXPECT_EQ(h.ng(), (Vec3{0, 0, 1}));  // a record no engine filled still decodes to a unit normal
  const Vec3 g = normalize(Vec3{0.3f, -0.8f, -0.2f}), s = normalize(Vec3{-0.1f, 0.2f, 0.97f});
  h.setNormals(g, s);
  EXPECT_LT(length(cross(h.ng(), g)), 1e-4f);
  EXPECT_GT(dot(h.ng(), g), 0);
  EXPECT_LT(length(cross(h.ns(), s)), 1e-4f);
  EXPECT_GT(dot(h.ns(), s), 0);
}

// The micro-quad index, the level and the border flag share one word: each keeps its largest
// value at the finest level --max-lod allows, and none spills into another.
TEST(RayHit, KeepsTheLastQuadOfTheFinestLevelBesideItsLevelAndBorderFlag) {
  RayHit h;
  const uint32_t lastQuad = (uint32_t(1) << (2 * kMaxHitLevel)) - 1;  // 4^12 quads at level 12
  h.quad = lastQuad;
  h.level = kMaxHitLevel;
  h.border = true;
  EXPECT_EQ(h.quad, lastQuad);
  EXPECT_EQ(h.level, uint32_t(kMaxHitLevel));
  EXPECT_TRUE(h.border);
  h.quad = 0;
  EXPECT_EQ(h.level, uint32_t(kMaxHitLevel));
  EXPECT_TRUE(h.border);
  h.border = false;
  h.level = 0;
  h.quad = lastQuad;
  EXPECT_EQ(h.level, 0u);
  EXPECT_FALSE(h.border);
  const RayHit none;
  EXPECT_EQ(none.quad, 0u);
  EXPECT_EQ(none.level, 0u);
  EXPECT_FALSE(none.border);
}

TEST(Octahedral, AxisAlignedNormalsRoundTripExactlyWhateverTheSignOfZero) {
  for (float z0 : {0.0f, -0.0f})
    for (Vec3 axis : {Vec3{1, z0, z0}, Vec3{-1, z0, z0}, Vec3{z0, 1, z0}, Vec3{z0, -1, z0}, Vec3{z0, z0, 1},
                      Vec3{z0, z0, -1}}) {
      const Vec3 d = decodeOctahedral(encodeOctahedral(axis));
      EXPECT_EQ(d.x, axis.x);
      EXPECT_EQ(d.y, axis.y);
      EXPECT_EQ(d.z, axis.z);
    }
}

TEST(Octahedral, AntipodalNormalsStayAntipodalAcrossTheFold) {
  // The lower hemisphere is folded over the octahedron's edges; normals close to the fold
  // (z just below 0, and near the x = 0 and y = 0 creases) are where a sign slip would show.
  for (uint32_t i = 0; i < 20000; ++i) {
    const RngKey k{i, 0, 0, 7};
    const float x = 2 * sampleUniform(k, 0) - 1, y = 2 * sampleUniform(k, 1) - 1;
    const float z = (i % 4 == 0) ? -1e-4f * sampleUniform(k, 2) : 2 * sampleUniform(k, 2) - 1;
    Vec3 n = normalize(Vec3{i % 3 == 0 ? 1e-6f * x : x, i % 5 == 0 ? -1e-6f * y : y, z});
    const Vec3 a = decodeOctahedral(encodeOctahedral(n)), b = decodeOctahedral(encodeOctahedral(-n));
    ASSERT_TRUE(unitAndFinite(a) && unitAndFinite(b)) << i;
    EXPECT_LT(length(cross(a, n)), 1e-4f) << i;
    EXPECT_GT(dot(a, n), 0) << i;
    EXPECT_LT(length(cross(b, n)), 1e-4f) << i;
    EXPECT_LT(dot(b, n), 0) << i;
  }
}

TEST(Octahedral, EveryCodeDecodesToAFiniteUnitVectorAndBadInputToPlusZ) {
  // Codes on a 17-step lattice of both coordinates, with the extremes (-32768 lies past -1).
  auto check = [](int x, int y) {
    const uint32_t code = uint32_t(uint16_t(int16_t(x))) | (uint32_t(uint16_t(int16_t(y))) << 16);
    return unitAndFinite(decodeOctahedral(code));
  };
  int bad = 0;
  for (int x = -32768; x <= 32767; x += 17)
    for (int y = -32768; y <= 32767; y += 17) bad += !check(x, y);
  for (int x : {-32768, -32767, -1, 0, 1, 32766, 32767})
    for (int y : {-32768, -32767, -1, 0, 1, 32766, 32767}) bad += !check(x, y);
  EXPECT_EQ(bad, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Vec3 n : {Vec3{0, 0, 0}, Vec3{nan, 0, 1}, Vec3{0, nan, 0}, Vec3{kInf, 0, 0}, Vec3{1, -kInf, 0},
                 Vec3{3e38f, 3e38f, 3e38f}})
    EXPECT_EQ(decodeOctahedral(encodeOctahedral(n)), (Vec3{0, 0, 1}));
  // A denormal-length direction keeps its direction.
  EXPECT_EQ(decodeOctahedral(encodeOctahedral({1e-40f, 0, 0})), (Vec3{1, 0, 0}));
}

TEST(RayBatch, AnUntimedBatchStoresNoTimeAndReadsTimeZero) {
  RayBatch timed, untimed;
  untimed.timed = false;
  timed.resize(3);
  untimed.resize(3);
  for (RayBatch* b : {&timed, &untimed})
    b->set(1, RayKind::Closest, {0, 0, 0}, {0, 0, 1}, kInf, 0, 0, kNoLeaf, kNoLeaf, 0, 0.75f);
  EXPECT_EQ(timed.timeOf(1), 0.75f);
  EXPECT_EQ(untimed.timeOf(1), 0.0f);
  EXPECT_TRUE(untimed.time.empty());
  EXPECT_EQ(RayBatch::bytesPerRay(true) - RayBatch::bytesPerRay(false), sizeof(float));
}

// Shadow pairs: slot 2k keeps a full hit (and its derivatives), slot 2k+1 only the leaf that
// occludes its shadow ray, so a pair costs one 28-byte hit and 4 bytes instead of two hits.
TEST(RayBatch, ShadowPairsKeepAFullHitInEvenSlotsAndAnOccluderLeafInOddSlots) {
  RayBatch b;
  b.shadowPairs = true;
  b.derivatives = true;
  b.resize(6);
  EXPECT_EQ(b.hit.size(), 3u);
  EXPECT_EQ(b.occluder.size(), 3u);
  EXPECT_EQ(b.dpd.size(), 3u);
  b.set(2, RayKind::Closest, {0, 0, 0}, {0, 0, 1}, kInf, 0, 0, kNoLeaf, kNoLeaf, 0, 0.0f);
  b.set(3, RayKind::Shadow, {0, 0, 0}, {1, 0, 0}, 2.0f, 0, 0, kNoLeaf, kNoLeaf, 0, 0.0f);
  EXPECT_TRUE(b.keepsFullHit(2));
  EXPECT_FALSE(b.keepsFullHit(3));
  b.hitOf(2).leaf = 7;
  b.hitOf(2).t = 1.5f;
  b.derivativesOf(2)->dpdu = {1, 2, 3};
  b.occluderOf(3) = 9;
  EXPECT_EQ(b.hit[1].leaf, 7u);  // slot 2's hit is the pair's
  EXPECT_EQ(b.dpd[1].dpdu, (Vec3{1, 2, 3}));
  EXPECT_EQ(b.occluder[1], 9u);
  EXPECT_TRUE(b.occluded(2));
  EXPECT_TRUE(b.occluded(3));
  b.clearHit(1);  // a slot's result means something once set, cleared or traced
  EXPECT_FALSE(b.occluded(1));
  EXPECT_EQ(b.occluderOf(2), 7u);  // a full slot's leaf word is its hit's
  b.clearHit(3);
  EXPECT_FALSE(b.occluded(3));
  EXPECT_TRUE(b.occluded(2));
  b.clearHit(2);
  EXPECT_FALSE(b.occluded(2));
  EXPECT_EQ(b.dpd[1].dpdu, (Vec3{0, 0, 0}));
  // An odd slot count: the last slot is even and keeps a full hit.
  b.resize(5);
  EXPECT_EQ(b.hit.size(), 3u);
  EXPECT_EQ(b.occluder.size(), 2u);
  b.resize(8);
  EXPECT_FALSE(b.occluded(5));
  EXPECT_FALSE(b.occluded(7)) << "a shadow slot a resize adds has no occluder";
}

// What a slot costs: the 36-byte ray and, per slot of a pair, half of one 28-byte hit and one
// 4-byte occluder (half of the 24-byte derivatives too, when kept); a full slot its own hit.
TEST(RayBatch, AShadowPairCostsOneHitAndOneOccluderLeaf) {
  EXPECT_EQ(RayBatch::bytesPerRay(false, false, false), 36u + 28u);
  EXPECT_EQ(RayBatch::bytesPerRay(false, false, true), 36u + (28u + 4u) / 2);
  EXPECT_EQ(RayBatch::bytesPerRay(false, true, true), 36u + (28u + 24u + 4u) / 2);
  EXPECT_EQ(RayBatch::bytesPerRay(true, false, true) - RayBatch::bytesPerRay(false, false, true), sizeof(float));
}

// The origin leaf, its level and the kind share one word of the 36-byte record: each keeps its
// extremes (the last leaf id a ray can name, the finest level, every kind) beside the others.
TEST(Ray, KeepsItsOriginLeafLevelAndKindInOneWord) {
  EXPECT_EQ(sizeof(Ray), 36u);
  RayBatch b;
  b.resize(1);
  const uint32_t lastLeaf = kMaxRayLeaves - 1;
  for (RayKind k : {RayKind::Inactive, RayKind::Closest, RayKind::Shadow}) {
    b.set(0, k, {0, 0, 0}, {0, 0, 1}, kInf, 0, 0, kNoLeaf, lastLeaf, uint8_t(kMaxHitLevel), 0.0f);
    EXPECT_EQ(b.ray[0].originLeaf(), lastLeaf);
    EXPECT_EQ(b.ray[0].originLevel, uint32_t(kMaxHitLevel));
    EXPECT_EQ(b.ray[0].kind, k);
    b.set(0, k, {0, 0, 0}, {0, 0, 1}, kInf, 0, 0, kNoLeaf, kNoLeaf, 0, 0.0f);
    EXPECT_EQ(b.ray[0].originLeaf(), kNoLeaf);
    EXPECT_EQ(b.ray[0].originLevel, 0u);
    EXPECT_EQ(b.ray[0].kind, k);
    b.set(0, k, {0, 0, 0}, {0, 0, 1}, kInf, 0, 0, kNoLeaf, 0, 1, 0.0f);
    EXPECT_EQ(b.ray[0].originLeaf(), 0u);
    EXPECT_EQ(b.ray[0].originLevel, 1u);
    EXPECT_EQ(b.ray[0].kind, k);
  }
  EXPECT_EQ(Ray{}.originLeaf(), kNoLeaf);
  EXPECT_EQ(Ray{}.kind, RayKind::Inactive);
}

}  // namespace
}  // namespace rayes
