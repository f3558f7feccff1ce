// collect(): order, completeness against brute force, resumption, tmax, edge cases.
#include <gtest/gtest.h>

#include <tbb/parallel_for.h>

#include "toplevel/toplevel_bvh.h"
#include "toplevel_test_util.h"

namespace rayes::testing {
namespace {

void expectStrictlyIncreasing(const std::vector<Candidate>& list) {
  for (size_t i = 1; i < list.size(); ++i)
    EXPECT_TRUE(candidateLess(list[i - 1], list[i])) << "at " << i;
}

// One call from the start returns the first maxCount of the brute-force list, and nextEntry
// is the entry of the first one left out.
void expectFirstCallMatches(const TopLevelBvh& bvh, const std::vector<Box3>& boxes,
                            const std::vector<TestRay>& rays, int maxCount) {
  TraversalScratch scratch;
  for (size_t r = 0; r < rays.size(); ++r) {
    SCOPED_TRACE(::testing::Message() << "ray " << r << ", maxCount " << maxCount);
    const std::vector<Candidate> all = bruteForce(boxes, rays[r]);
    const Collected c = collectOnce(bvh, rays[r], maxCount, scratch);
    const size_t n = std::min(all.size(), size_t(maxCount));
    ASSERT_EQ(c.list, std::vector<Candidate>(all.begin(), all.begin() + n));
    expectStrictlyIncreasing(c.list);
    EXPECT_EQ(c.nextEntry, n < all.size() ? all[n].entry : kInf);
  }
}

// The SortedEngine keeps only each ray's next candidate (nextEntry and the leaf collect() gives
// with it) and resumes just before it (TopLevelBvh::resumeBefore): collecting maxCount at a time
// that way yields the whole brute-force list too, ties of equal entries and leaf 0 included.
void expectResumingAtNextMatches(const TopLevelBvh& bvh, const std::vector<Box3>& boxes,
                                 const std::vector<TestRay>& rays, int maxCount) {
  TraversalScratch scratch;
  std::vector<Candidate> list(static_cast<size_t>(maxCount));
  for (size_t r = 0; r < rays.size(); ++r) {
    SCOPED_TRACE(::testing::Message() << "ray " << r << ", maxCount " << maxCount << ", resumed at the next");
    const std::vector<Candidate> all = bruteForce(boxes, rays[r]);
    std::vector<Candidate> got;
    float nextEntry = -kInf;  // the engine's initial state: at or after (-inf, 0), so everything
    uint32_t nextLeaf = 0;
    for (size_t calls = 0; calls <= all.size() + 1 && nextEntry < kInf; ++calls) {
      float resumeEntry;
      uint32_t resumeLeaf;
      TopLevelBvh::resumeBefore(nextEntry, nextLeaf, resumeEntry, resumeLeaf);
      const int n = bvh.collect(rays[r].org, rays[r].dir, rays[r].tmin, rays[r].tmax, resumeEntry, resumeLeaf,
                                list.data(), maxCount, nextEntry, scratch, &nextLeaf);
      got.insert(got.end(), list.begin(), list.begin() + n);
      if (nextEntry < kInf) {
        ASSERT_LT(got.size(), all.size());
        EXPECT_EQ(nextEntry, all[got.size()].entry);  // the next candidate, exactly
        EXPECT_EQ(nextLeaf, all[got.size()].leaf);
      }
    }
    ASSERT_EQ(got, all);
  }
}

// Collecting maxCount at a time from the last returned (entry, leaf) yields the whole
// brute-force list; nextEntry never exceeds the next returned entry and is +inf at the end.
void expectResumptionMatches(const TopLevelBvh& bvh, const std::vector<Box3>& boxes,
                             const std::vector<TestRay>& rays, int maxCount) {
  TraversalScratch scratch;
  for (size_t r = 0; r < rays.size(); ++r) {
    SCOPED_TRACE(::testing::Message() << "ray " << r << ", maxCount " << maxCount);
    const std::vector<Candidate> all = bruteForce(boxes, rays[r]);
    std::vector<Candidate> got;
    float resumeEntry = -kInf, previousNext = -kInf;
    uint32_t resumeLeaf = 0;
    for (size_t calls = 0; calls <= all.size() + 1; ++calls) {
      const Collected c = collectOnce(bvh, rays[r], maxCount, scratch, resumeEntry, resumeLeaf);
      if (!c.list.empty()) {
        EXPECT_LE(previousNext, c.list.front().entry);
        EXPECT_EQ(previousNext == -kInf ? c.list.front().entry : previousNext,
                  c.list.front().entry);  // exact: this implementation's nextEntry is tight
        resumeEntry = c.list.back().entry;
        resumeLeaf = c.list.back().leaf;
      }
      got.insert(got.end(), c.list.begin(), c.list.end());
      previousNext = c.nextEntry;
      if (int(c.list.size()) < maxCount) {
        EXPECT_EQ(c.nextEntry, kInf);
      }
      if (c.nextEntry == kInf) break;
    }
    EXPECT_EQ(previousNext, kInf);
    ASSERT_EQ(got, all);
  }
  expectResumingAtNextMatches(bvh, boxes, rays, maxCount);
}

struct Scene {
  std::vector<Box3> boxes;
  std::vector<TestRay> rays;
  TopLevelBvh bvh;
  Scene(int boxCount, int rayCount, uint64_t seed, float scale = 1, float offset = 0)
      : boxes(randomBoxes(boxCount, seed, scale, offset)),
        rays(randomRays(rayCount, seed + 1, boxes, scale, offset)) {
    bvh.build(boxes);
  }
};

TEST(Collect, RandomSceneMatchesBruteForce) {
  const Scene s(4000, 400, 11);
  // The scene must exercise the cases the test is about.
  int deep = 0, startInside = 0, axisParallel = 0;
  for (const TestRay& r : s.rays) {
    deep += bruteForce(s.boxes, r).size() > 100;
    axisParallel += r.dir.x == 0 || r.dir.y == 0 || r.dir.z == 0;
    for (const Box3& b : s.boxes) {
      if (b.contains(r.org + r.dir * r.tmin)) { ++startInside; break; }
    }
  }
  EXPECT_GT(deep, 10);
  EXPECT_GT(startInside, 40);
  EXPECT_GT(axisParallel, 40);
  for (int n : {1, 3, 8, 100}) expectFirstCallMatches(s.bvh, s.boxes, s.rays, n);
}

TEST(Collect, ResumptionReproducesBruteForce) {
  const Scene s(2000, 150, 21);
  for (int n = 1; n <= 7; ++n) expectResumptionMatches(s.bvh, s.boxes, s.rays, n);
}

TEST(Collect, NothingBeyondTmax) {
  Scene s(3000, 200, 31);
  int cut = 0;
  TraversalScratch scratch;
  for (TestRay& r : s.rays) {
    const size_t unbounded = bruteForce(s.boxes, {r.org, r.dir, r.tmin, kInf}).size();
    r.tmax = r.tmin + 30;
    const Collected c = collectOnce(s.bvh, r, 1000000, scratch);
    for (const Candidate& k : c.list) EXPECT_LE(k.entry, r.tmax);
    EXPECT_EQ(c.list, bruteForce(s.boxes, r));
    EXPECT_EQ(c.nextEntry, kInf);
    cut += c.list.size() < unbounded;
  }
  EXPECT_GT(cut, 50);  // tmax did remove candidates
}

TEST(Collect, ScaledAndTranslatedScenes) {
  for (auto [scale, offset] : {std::pair{1e-3f, 0.0f}, {1e4f, 0.0f}, {1.0f, 1e6f}}) {
    SCOPED_TRACE(::testing::Message() << "scale " << scale << " offset " << offset);
    const Scene s(1500, 150, 41, scale, offset);
    for (int n : {1, 8}) expectFirstCallMatches(s.bvh, s.boxes, s.rays, n);
    expectResumptionMatches(s.bvh, s.boxes, s.rays, 3);
  }
}

TEST(Collect, NoLeaves) {
  TopLevelBvh bvh;
  TraversalScratch scratch;
  const TestRay ray{{-1, 0.5f, 0.5f}, {1, 0, 0}};
  for (const std::vector<Box3>& boxes : {std::vector<Box3>{}, std::vector<Box3>(5)}) {
    bvh.build(boxes);
    EXPECT_EQ(bvh.leafCount(), boxes.size());
    EXPECT_EQ(bvh.nodeCount(), 0u);
    EXPECT_EQ(bvh.bytes(), boxes.size() * sizeof(Box3)) << "no node, only the boxes it was given";
    EXPECT_TRUE(bvh.bounds().empty());
    const Collected c = collectOnce(bvh, ray, 4, scratch);
    EXPECT_TRUE(c.list.empty());
    EXPECT_EQ(c.nextEntry, kInf);
  }
  // A default-constructed tree behaves the same.
  const TopLevelBvh fresh;
  EXPECT_TRUE(collectOnce(fresh, ray, 4, scratch).list.empty());
}

TEST(Collect, OneLeaf) {
  std::vector<Box3> boxes(3);  // ids 0 and 2 empty
  boxes[1] = {{0, 0, 0}, {1, 1, 1}};
  TopLevelBvh bvh;
  bvh.build(boxes);
  EXPECT_EQ(bvh.nodeCount(), 0u);  // the root is the leaf
  EXPECT_EQ(bvh.bounds().lo, boxes[1].lo);
  EXPECT_EQ(bvh.bounds().hi, boxes[1].hi);
  TraversalScratch scratch;
  const TestRay hit{{-2, 0.5f, 0.5f}, {1, 0, 0}};
  const Collected c = collectOnce(bvh, hit, 4, scratch);
  ASSERT_EQ(c.list, (std::vector<Candidate>{{1, 2.0f}}));
  EXPECT_EQ(c.nextEntry, kInf);
  const Collected none = collectOnce(bvh, hit, 0, scratch);  // only the bound
  EXPECT_TRUE(none.list.empty());
  EXPECT_EQ(none.nextEntry, 2.0f);
  EXPECT_TRUE(collectOnce(bvh, hit, 4, scratch, 2.0f, 1).list.empty());  // resumed past it
  EXPECT_EQ(collectOnce(bvh, hit, 4, scratch, 2.0f, 0).list.size(), 1u);
  const TestRay miss{{-2, 1.5f, 0.5f}, {1, 0, 0}};
  EXPECT_TRUE(collectOnce(bvh, miss, 4, scratch).list.empty());
  const TestRay inside{{0.5f, 0.5f, 0.5f}, {0, 0, -1}, 0.25f};  // enters at tmin
  ASSERT_EQ(collectOnce(bvh, inside, 4, scratch).list, (std::vector<Candidate>{{1, 0.25f}}));
}

TEST(Collect, IdenticalBoxesComeOutByLeafId) {
  std::vector<Box3> boxes(1000, Box3{{0, 0, 0}, {1, 1, 1}});
  boxes[7] = Box3{};  // an empty id in between is skipped
  TopLevelBvh bvh;
  bvh.build(boxes);
  const std::vector<TestRay> rays = {{{-1, 0.5f, 0.5f}, {1, 0, 0}},
                                     {{0.5f, 0.5f, 0.5f}, normalize(Vec3{1, 2, 3})},
                                     {{0, 0.5f, -3}, {0, 0, 1}}};  // along a face
  for (int n : {1, 3, 8, 100}) expectFirstCallMatches(bvh, boxes, rays, n);
  for (int n : {1, 7}) expectResumptionMatches(bvh, boxes, rays, n);
  TraversalScratch scratch;
  const Collected c = collectOnce(bvh, rays[0], 5, scratch);
  ASSERT_EQ(c.list, (std::vector<Candidate>{{0, 1}, {1, 1}, {2, 1}, {3, 1}, {4, 1}}));
}

// Leaf 0 as the next candidate after another leaf, at the same entry as leaf 2: resuming just
// before (entry, 0) must take the float below the entry, since no leaf lies before 0.
TEST(Collect, ResumingAtLeafZeroAfterAnotherLeaf) {
  const std::vector<Box3> boxes = {Box3{{2, -1, -1}, {5, 1, 1}}, Box3{{0, -1, -1}, {5, 1, 1}},
                                   Box3{{2, -1, -1}, {6, 1, 1}}};
  TopLevelBvh bvh;
  bvh.build(boxes);
  const std::vector<TestRay> rays = {{{-1, 0.25f, 0.5f}, {1, 0, 0}}};
  ASSERT_EQ(bruteForce(boxes, rays[0]).size(), 3u);
  ASSERT_EQ(bruteForce(boxes, rays[0])[1].leaf, 0u);
  for (int n : {1, 2}) expectResumingAtNextMatches(bvh, boxes, rays, n);
}

TEST(Collect, ThreadsAgreeAndScratchStopsGrowing) {
  const Scene s(3000, 500, 51);
  std::vector<std::vector<Candidate>> serial(s.rays.size());
  TraversalScratch scratch;
  for (size_t r = 0; r < s.rays.size(); ++r) serial[r] = collectOnce(s.bvh, s.rays[r], 8, scratch).list;
  // A second pass over the same rays must not reallocate the traversal stack.
  const auto* heapData = scratch.heap.data();
  for (const TestRay& r : s.rays) collectOnce(s.bvh, r, 8, scratch);
  EXPECT_EQ(scratch.heap.data(), heapData);

  std::vector<std::vector<Candidate>> parallel(s.rays.size());
  tbb::parallel_for(size_t(0), s.rays.size(), [&](size_t r) {
    TraversalScratch local;
    parallel[r] = collectOnce(s.bvh, s.rays[r], 8, local).list;
  });
  EXPECT_EQ(parallel, serial);
}

TEST(Collect, RebuildReplacesTree) {
  TopLevelBvh bvh;
  bvh.build(randomBoxes(500, 61));
  const std::vector<Box3> boxes = randomBoxes(300, 62);
  bvh.build(boxes);
  EXPECT_EQ(bvh.leafCount(), 300u);
  expectFirstCallMatches(bvh, boxes, randomRays(50, 63, boxes), 8);
}

}  // namespace
}  // namespace rayes::testing
