// DiceBuffer::mayEnterRegionBox: a static dicing tests a ray against a coarse box around a border
// segment's region box (Patch::coarseBoundsOverAt and the chord) before it computes the box, and
// skips the segment when the ray misses it. That must change nothing but the work: the same
// hits and occluders, bit for bit, as a dicing of the same patch that computes every box the walk
// reaches, with fewer boxes computed; and the same under concurrent queries of one dicing.
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>
#include <atomic>
#include <limits>
#include <memory>
#include <vector>
#include "dicing/dice_buffer.h"
#include "geometry/bezier_patch.h"
#include "geometry/displaced_patch.h"
#include "geometry/displacement.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

// A displaced patch seen through a forwarding patch that counts boundsOver calls and, unless
// `coarse`, offers no coarse box (the Patch default): the dicing then computes every box the
// walk reaches, as before the coarse test existed.
class CountingPatch final : public Patch {
 public:
  CountingPatch(PatchPtr p, bool coarse) : p_(std::move(p)), coarse_(coarse) {}
  Box3 bounds() const override { return p_->bounds(); }
  Box3 boundsOver(float u0, float u1, float v0, float v1) const override {
    calls.fetch_add(1, std::memory_order_relaxed);
    return p_->boundsOver(u0, u1, v0, v1);
  }
  float sizeBound() const override { return p_->sizeBound(); }
  SurfacePoint evaluate(float u, float v) const override { return p_->evaluate(u, v); }
  void dice(int level, Vec3* positions, Vec3* normals) const override { p_->dice(level, positions, normals); }
  float dicingErrorCoefficient() const override { return p_->dicingErrorCoefficient(); }
  const char* kind() const override { return p_->kind(); }
  bool isDisplaced() const override { return p_->isDisplaced(); }
  bool needsBorderClosure() const override { return p_->needsBorderClosure(); }
  void borderPieceBoundsAt(int sample, int e, int k, uint32_t j, int split, Box3* out) const override {
    p_->borderPieceBoundsAt(sample, e, k, j, split, out);
  }
  bool coarseBoundsOverAt(int sample, float u0, float u1, float v0, float v1, Box3& out) const override {
    return coarse_ && p_->coarseBoundsOverAt(sample, u0, u1, v0, v1, out);
  }
  mutable std::atomic<int> calls{0};

 private:
  PatchPtr p_;
  bool coarse_;
};

PatchPtr displacedTeapot(float amplitude) {
  NoiseParams noise;
  noise.amplitude = amplitude;
  noise.frequency = 3.0f;
  noise.octaves = 4;
  return std::make_shared<DisplacedPatch>(std::make_shared<BezierPatch>(test::loadTeapot()[0]),
                                          std::make_shared<NoiseDisplacement>(noise));
}

struct TestRay {
  Vec3 org, dir;
  int level;
};

// Rays at border points from outside along a perturbed normal (they walk the border regions
// down to their level), and rays through the patch's box from every side (most miss the
// borders' coarse boxes or meet them only high in the walk).
std::vector<TestRay> testRays(const Patch& patch, int m) {
  test::Random rnd(11);
  std::vector<TestRay> rays;
  for (int r = 0; r < 800; ++r) {
    const test::BorderRay ray = test::randomBorderRay(patch, rnd, 0.0f, 1.0f, m);
    rays.push_back({ray.org, ray.dir, ray.level});
  }
  const Box3 b = patch.bounds();
  const Vec3 c = (b.lo + b.hi) * 0.5f;
  const float r = length(b.hi - b.lo);
  for (int k = 0; k < 800; ++k) {
    const Vec3 d = normalize(Vec3{rnd.uniform(-1.0f, 1.0f), rnd.uniform(-1.0f, 1.0f), rnd.uniform(-1.0f, 1.0f)});
    const Vec3 target = b.lo + (b.hi - b.lo) * Vec3{rnd.uniform(), rnd.uniform(), rnd.uniform()};
    rays.push_back({c - d * (2.0f * r) + (target - c), d, rnd.below(m + 1)});
  }
  return rays;
}

bool sameHit(const GridHit& a, const GridHit& b) {
  return a.t == b.t && a.u == b.u && a.v == b.v && a.quad == b.quad && a.border == b.border && a.ng == b.ng &&
         a.ns == b.ns && a.dpdu == b.dpdu && a.dpdv == b.dpdv;
}

// A low relief (2 % of the patch), where a coarse box is little larger than the box it holds.
TEST(CoarseRegionBox, SkipsBoxesWithoutChangingAHit) {
  constexpr int m = 6;
  const PatchPtr base = displacedTeapot(0.002f);
  const CountingPatch every(base, false), coarse(base, true);
  DiceBuffer a(m), b(m);
  a.dice(every, m);
  b.dice(coarse, m);
  const int diceCallsA = every.calls.load(), diceCallsB = coarse.calls.load();
  BottomQuery q;
  q.closeBorders = true;
  int hits = 0, borderHits = 0;
  for (const TestRay& r : testRays(*base, m)) {
    GridHit ha, hb;
    const bool fa = a.intersect(r.org, r.dir, 0.0f, kInf, r.level, ha, q);
    ASSERT_EQ(b.intersect(r.org, r.dir, 0.0f, kInf, r.level, hb, q), fa);
    if (fa) {
      ASSERT_TRUE(sameHit(ha, hb)) << ha.t << " " << hb.t;
      ++hits;
      borderHits += ha.border;
    }
    ASSERT_EQ(b.occluded(r.org, r.dir, 0.0f, kInf, r.level, q), a.occluded(r.org, r.dir, 0.0f, kInf, r.level, q));
  }
  EXPECT_GT(borderHits, 0);  // the regions were reached
  EXPECT_GT(hits, borderHits);
  // Every box the coarse dicing computed is one the full dicing computed too, and some were spared.
  const int boxesA = every.calls.load() - diceCallsA, boxesB = coarse.calls.load() - diceCallsB;
  EXPECT_LT(boxesB, boxesA);
  EXPECT_GT(boxesB, 0);
  // The boxes it did compute are the same bits (a later query of a skipped segment computes it).
  for (int e = 0; e < 4; ++e)
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j < (1 << i); ++j) {
        const Box3 x = a.borderNode(e, i, j), y = b.borderNode(e, i, j);
        ASSERT_TRUE(x.lo == y.lo && x.hi == y.hi) << e << " " << i << " " << j;
      }
}

// Concurrent queries of one dicing (a large run's chunks) fill its coarse and exact boxes in
// whatever order: each ray gets the hit of a serial query of a fresh dicing.
TEST(CoarseRegionBox, ConcurrentQueriesOfOneDicingGetTheSerialHits) {
  constexpr int m = 6;
  const PatchPtr base = displacedTeapot(0.05f);
  const CountingPatch coarse(base, true);
  const std::vector<TestRay> rays = testRays(*base, m);
  BottomQuery q;
  q.closeBorders = true;
  DiceBuffer serial(m), shared(m);
  serial.dice(coarse, m);
  shared.dice(coarse, m);
  std::vector<GridHit> expected(rays.size());
  std::vector<char> found(rays.size());
  for (size_t k = 0; k < rays.size(); ++k)
    found[k] = serial.intersect(rays[k].org, rays[k].dir, 0.0f, kInf, rays[k].level, expected[k], q);
  std::atomic<int> mismatches{0};
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t k) {
    GridHit h;
    const bool f = shared.intersect(rays[k].org, rays[k].dir, 0.0f, kInf, rays[k].level, h, q);
    if (f != bool(found[k]) || (f && !sameHit(h, expected[k]))) mismatches.fetch_add(1);
  });
  EXPECT_EQ(mismatches.load(), 0);
}

// The per-dicing entries carry 16-bit stamps: after 65,535 dicings of one buffer the stamps start
// again, and no box or coarse box of a dicing before that may be taken for a later one's.
TEST(CoarseRegionBox, StampsWrapAroundWithoutStaleBoxes) {
  constexpr int m = 2;
  const PatchPtr first = displacedTeapot(0.05f), later = displacedTeapot(0.2f);
  const BezierPatch plain(test::loadTeapot()[1]);
  DiceBuffer buffer(m), fresh(m);
  buffer.dice(*first, m);
  for (int e = 0; e < 4; ++e)
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j < (1 << i); ++j) buffer.borderNode(e, i, j);  // every entry filled
  for (int k = 0; k < 65534; ++k) buffer.dice(plain, 0);
  buffer.dice(*later, m);  // the stamp wraps here
  fresh.dice(*later, m);
  for (int e = 0; e < 4; ++e)
    for (int i = 0; i <= m; ++i)
      for (int j = 0; j < (1 << i); ++j) {
        const Box3 x = buffer.borderNode(e, i, j), y = fresh.borderNode(e, i, j);
        ASSERT_TRUE(x.lo == y.lo && x.hi == y.hi) << e << " " << i << " " << j;
      }
}

}  // namespace
}  // namespace rayes
