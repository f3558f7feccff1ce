// The procedural forest (geometry/forest.h): a leaf's patch stays inside the box recorded for
// it (invariant 1, by sampling and by dicing), the forest is a pure function of its parameters
// whatever the thread count, tubes and terrain are watertight at shared borders, the counts
// are what leafCount() predicts, and bad parameters are refused before anything is grown.
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <tbb/global_control.h>
#include "geometry/displaced_patch.h"
#include "geometry/forest.h"
#include "support/patch_test_util.h"

namespace rayes {
namespace {

ForestParams smallForest() {
  ForestParams p;
  p.trees = 3;
  p.seed = 42;
  p.detail = 3;
  p.area = 20;
  p.terrainTiles = 4;
  p.leavesPerTwig = 4;
  return p;
}

TEST(Forest, CountsAreWhatLeafCountPredicts) {
  const ForestParams p = smallForest();
  const Forest f(p);
  EXPECT_EQ(f.size(), Forest::leafCount(p));
  // Branches: 1 + 3 + 9 + 27 per tree; the trunk has 3 segments, the others 2; 4 quarters each.
  EXPECT_EQ(f.branchCount(), 3u * 40u);
  EXPECT_EQ(f.countOf(ForestLeaf::Part::Bark), 3u * 4u * (3 + 39 * 2));
  EXPECT_EQ(f.countOf(ForestLeaf::Part::Foliage), 3u * 27u * 4u);
  EXPECT_EQ(f.countOf(ForestLeaf::Part::Terrain), 16u);
  EXPECT_GT(f.bytesPerLeaf(), 0);
  EXPECT_LT(f.bytesPerLeaf(), 80);  // compact: records and boxes, not patches
}

TEST(Forest, EveryPatchLiesInsideItsRecordedBound) {
  const Forest f(smallForest());
  test::Random rnd(7);
  std::vector<Vec3> pos, nrm;
  for (size_t i = 0; i < f.size(); ++i) {
    const PatchPtr patch = f.makePatch(i);
    const Box3& box = f.bounds(i);
    ASSERT_FALSE(box.empty()) << i;
    for (int k = 0; k < 64; ++k) {
      const SurfacePoint sp = patch->evaluate(rnd.uniform(), rnd.uniform());
      ASSERT_TRUE(box.contains(sp.p)) << "leaf " << i << " (" << patch->kind() << ")";
    }
    const int level = 3, side = (1 << level) + 1;
    pos.resize(size_t(side) * side);
    nrm.resize(pos.size());
    patch->dice(level, pos.data(), nrm.data());
    for (const Vec3& p : pos) ASSERT_TRUE(box.contains(p)) << "leaf " << i;
  }
}

TEST(Forest, SameSeedSameForestOnAnyThreadCount) {
  auto grow = [](int threads, uint64_t seed) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    ForestParams p = smallForest();
    p.seed = seed;
    return Forest(p);
  };
  const Forest a = grow(1, 42), b = grow(2, 42), c = grow(2, 43);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.leaf(i), &b.leaf(i), sizeof(ForestLeaf)), 0) << i;
    EXPECT_EQ(std::memcmp(&a.bounds(i), &b.bounds(i), sizeof(Box3)), 0) << i;
  }
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a.bounds(i), &c.bounds(i), sizeof(Box3)) != 0;
  EXPECT_GT(differ, a.size() / 2);  // another seed grows another forest
}

// Border rows of a level-m dicing: u = 0 (i = 0), u = 1, v = 0 (j = 0), v = 1.
std::vector<Vec3> borderOf(const Patch& patch, int level, int which) {
  const int n = (1 << level) + 1;
  std::vector<Vec3> pos(size_t(n) * n), nrm(pos.size()), out;
  patch.dice(level, pos.data(), nrm.data());
  for (int k = 0; k < n; ++k) {
    const int i = which == 0 ? 0 : which == 1 ? n - 1 : k, j = which == 2 ? 0 : which == 3 ? n - 1 : k;
    out.push_back(pos[size_t(j) * n + i]);
  }
  return out;
}

bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(Forest, TubesAreWatertightAlongAndAround) {
  ForestParams p = smallForest();
  p.terrainAmplitude = 0;  // bark only: the terrain is checked below
  const Forest f(p);
  // Leaves of one branch are consecutive: segment-major, quarter-minor.
  size_t checked = 0;
  for (size_t i = 0; i + 1 < f.size(); ++i) {
    const ForestLeaf& a = f.leaf(i);
    if (a.part != ForestLeaf::Part::Bark) continue;
    const Forest::Branch& br = f.branch(a.index);
    const size_t first = i - (size_t(a.segment) * 4 + a.quarter);
    // Around: quarter q's u = 1 border is quarter q+1's u = 0 border (quarter 3 closes on 0).
    const size_t around = first + size_t(a.segment) * 4 + (a.quarter + 1) % 4;
    // The base tubes share borders bit for bit. (Displaced, they differ by the rounding of
    // each side's own base normal, like every displaced seam: the border regions close that.)
    auto baseOf = [](const PatchPtr& p) -> const Patch& { return dynamic_cast<const DisplacedPatch&>(*p).base(); };
    const PatchPtr pi = f.makePatch(i), pa = f.makePatch(around);
    EXPECT_TRUE(sameBits(borderOf(baseOf(pi), 3, 1), borderOf(baseOf(pa), 3, 0))) << i;
    if (a.segment + 1 < br.segments) {
      const PatchPtr pn = f.makePatch(first + size_t(a.segment + 1) * 4 + a.quarter);
      EXPECT_TRUE(sameBits(borderOf(baseOf(pi), 3, 3), borderOf(baseOf(pn), 3, 2))) << i;
    }
    ++checked;
  }
  EXPECT_GT(checked, 100u);
}

TEST(Forest, TerrainTilesShareTheirBorders) {
  const ForestParams p = smallForest();
  const Forest f(p);
  const size_t n = size_t(p.terrainTiles);
  for (size_t j = 0; j < n; ++j)
    for (size_t i = 0; i + 1 < n; ++i)
      EXPECT_TRUE(sameBits(borderOf(*f.makePatch(j * n + i), 4, 1), borderOf(*f.makePatch(j * n + i + 1), 4, 0)));
}

// A placed forest is the unplaced one mapped by its similarity: every dicing vertex (bark and
// terrain heights included, which scale with it) is the placed unplaced vertex, to rounding:
// 8 ulps of the largest placed coordinate -- the placement's own (a 3-term dot product, about
// 2 ulps) and the patch's evaluation from placed control points (a few ulps of them).
TEST(Forest, APlacementMapsTheWholeForest) {
  ForestParams p = smallForest();
  const Forest unplaced(p);
  const float s = 1e3f;
  const Vec3 offset{1e4f, -2e3f, 5e2f};
  p.placement = Transform::translate(offset) * Transform::rotate({0, 1, 1}, 30) * Transform::scale({s, s, s});
  const Forest placed(p);
  ASSERT_EQ(placed.size(), unplaced.size());
  std::vector<Vec3> a, na, b, nb;
  const int level = 3, side = (1 << level) + 1;
  for (std::vector<Vec3>* v : {&a, &na, &b, &nb}) v->resize(size_t(side) * side);
  float largest = 0;
  for (size_t i = 0; i < placed.size(); ++i)
    for (int k = 0; k < 3; ++k)
      largest = std::max({largest, std::fabs(placed.bounds(i).lo[k]), std::fabs(placed.bounds(i).hi[k])});
  const float tolerance = 8 * std::numeric_limits<float>::epsilon() * largest;
  float worst = 0;
  for (size_t i = 0; i < placed.size(); i += 7) {
    unplaced.makePatch(i)->dice(level, a.data(), na.data());
    const PatchPtr patch = placed.makePatch(i);
    patch->dice(level, b.data(), nb.data());
    const Box3& box = placed.bounds(i);
    for (size_t k = 0; k < a.size(); ++k) {
      ASSERT_TRUE(box.contains(b[k])) << "leaf " << i;
      worst = std::max(worst, length(b[k] - p.placement.point(a[k])));
    }
  }
  EXPECT_LE(worst, tolerance);
}

TEST(Forest, OnlySimilaritiesPlaceAForest) {
  EXPECT_EQ(Forest::placementScale(Transform{}), 0.0f);
  EXPECT_NEAR(Forest::placementScale(Transform::rotate({1, 2, 3}, 70) * Transform::scale({3, 3, 3})), 3.0f, 1e-5f);
  EXPECT_THROW(Forest::placementScale(Transform::scale({1, 2, 1})), std::invalid_argument);
  EXPECT_THROW(Forest::placementScale(Transform::scale({-1, 1, 1})), std::invalid_argument);
  EXPECT_THROW(Forest::placementScale(Transform::scale({0, 0, 0})), std::invalid_argument);
  Transform shear;
  shear.m[0][1] = 0.5f;
  EXPECT_THROW(Forest::placementScale(shear), std::invalid_argument);
}

TEST(Forest, BadParametersAreRefusedBeforeGrowing) {
  auto refused = [](auto change) {
    ForestParams p = smallForest();
    change(p);
    try {
      Forest f(p, 1'000'000);
      return false;
    } catch (const std::invalid_argument&) {
      return true;
    }
  };
  EXPECT_TRUE(refused([](ForestParams& p) { p.detail = -1; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.detail = ForestParams::kMaxDetail + 1; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.branching = 0; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.area = 0; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.area = std::numeric_limits<float>::quiet_NaN(); }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.treeHeight = -2; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.terrainTiles = 0; }));
  EXPECT_TRUE(refused([](ForestParams& p) { p.leavesPerTwig = -1; }));
  // Absurd detail: more leaves than the limit allows, refused by count (nothing is grown).
  EXPECT_TRUE(refused([](ForestParams& p) { p.trees = 100000; p.detail = 8; p.branching = 6; }));
  // The count does not wrap around in 64 bits: 4e9 trees of 6^8 twigs each.
  ForestParams absurd;
  absurd.trees = 4'000'000'000u;
  absurd.detail = ForestParams::kMaxDetail;
  absurd.branching = ForestParams::kMaxBranching;
  absurd.leavesPerTwig = ForestParams::kMaxLeavesPerTwig;
  EXPECT_GT(double(Forest::leafCount(absurd)), 4.9e17);
  EXPECT_FALSE(refused([](ForestParams&) {}));
}

}  // namespace
}  // namespace rayes
