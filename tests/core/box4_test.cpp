// core/box4.h: the 4-wide slab test is intersectBox lane by lane, to the bit, on the inputs where
// the scalar test has to be careful (zero direction components, origins on slab planes, NaN slab
// distances, inverted and infinite boxes, empty segments).
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <gtest/gtest.h>
#include "core/box4.h"
#include "core/rng.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// Runs both tests on four boxes and one ray and requires the same hits and, for hits, the same bits.
void expectLanesMatchScalar(const std::array<Box3, 4>& boxes, Vec3 org, Vec3 dir, float tmin, float tmax) {
  const RayBoxQuery q(org, dir);
  __m128 nearPlane[3], farPlane[3];
  for (int a = 0; a < 3; ++a) {
    float lo[4], hi[4];
    for (int i = 0; i < 4; ++i) { lo[i] = boxes[i].lo[a]; hi[i] = boxes[i].hi[a]; }
    nearPlane[a] = _mm_loadu_ps(q.sign[a] ? hi : lo);
    farPlane[a] = _mm_loadu_ps(q.sign[a] ? lo : hi);
  }
  __m128 entry4, exit4;
  const unsigned mask = intersectBox4(RayBox4Query(q), nearPlane, farPlane, _mm_set1_ps(tmin), _mm_set1_ps(tmax),
                                      entry4, exit4);
  alignas(16) float entry[4], exit[4];
  _mm_store_ps(entry, entry4);
  _mm_store_ps(exit, exit4);
  for (int i = 0; i < 4; ++i) {
    float e, x;
    const bool hit = intersectBox(q, boxes[i].lo, boxes[i].hi, tmin, tmax, e, x);
    ASSERT_EQ(((mask >> i) & 1) != 0, hit) << "lane " << i;
    ASSERT_EQ(std::bit_cast<uint32_t>(entry[i]), std::bit_cast<uint32_t>(e)) << "lane " << i;
    ASSERT_EQ(std::bit_cast<uint32_t>(exit[i]), std::bit_cast<uint32_t>(x)) << "lane " << i;
    if (hit) {
      EXPECT_FALSE(std::isnan(entry[i]));
      EXPECT_FALSE(std::isnan(exit[i]));
    }
  }
}

TEST(Box4, EdgeCasesMatchTheScalarTestBitForBit) {
  const Box3 unit{{-1, -1, -1}, {1, 1, 1}};
  const Box3 flat{{-1, -1, 0}, {1, 1, 0}};
  const Box3 far{{1e30f, 1e30f, 1e30f}, {3e38f, 3e38f, 3e38f}};
  const Box3 infinite{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}};
  const std::array<Box3, 4> boxes{unit, flat, far, Box3{}};  // Box3{} is inverted (empty)
  const std::array<Box3, 4> more{infinite, Box3{{0, 0, 0}, {0, 0, 0}}, unit, flat};
  const Vec3 origins[] = {{-5, -5, -5}, {1, 0, -3}, {-1, -1, -1}, {0, 0, 0}, {0, 1, 0}, {2e38f, 2e38f, 2e38f}};
  const Vec3 dirs[] = {{1, 1, 1}, {0, 0, 1}, {0, 1, 0}, {-1, 0, 0}, {0, 0, 0}, {-0.0f, 0.0f, -1}, {1e-30f, -1, 0}};
  const float ranges[][2] = {{0, kInf}, {0, 0}, {2, 1}, {-kInf, kInf}, {0.5f, 4}};
  for (const Vec3& o : origins)
    for (const Vec3& d : dirs)
      for (const auto& r : ranges) {
        expectLanesMatchScalar(boxes, o, d, r[0], r[1]);
        expectLanesMatchScalar(more, o, d, r[0], r[1]);
      }
}

TEST(Box4, RandomBoxesAndRaysMatchTheScalarTestBitForBit) {
  uint32_t dim = 0;
  auto uniform = [&] { return sampleUniform(RngKey{.seed = 7}, dim++); };
  auto coord = [&] { return 4.0f * uniform() - 2.0f; };
  for (int n = 0; n < 2000; ++n) {
    std::array<Box3, 4> boxes;
    for (Box3& b : boxes) {
      b.extend(Vec3{coord(), coord(), coord()});
      b.extend(Vec3{coord(), coord(), coord()});
    }
    // Directions with exact zeros now and then, so the 0 * inf slabs are exercised too.
    Vec3 d{coord(), coord(), coord()};
    for (int a = 0; a < 3; ++a)
      if (uniform() < 0.2f) d[a] = 0;
    expectLanesMatchScalar(boxes, Vec3{3 * coord(), 3 * coord(), 3 * coord()}, d, 0, 1 + 10 * uniform());
  }
}

}  // namespace
}  // namespace rayes
