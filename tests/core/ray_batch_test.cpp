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

}  // namespace
}  // namespace rayes
