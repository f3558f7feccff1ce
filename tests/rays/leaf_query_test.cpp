// Leaf queries (core/leaf_queries.h) reach the runner exactly once each, in calls of one leaf's
// slots in increasing order (one call per leaf, or consecutive chunks of a leaf with many
// queries), during the same trace() as the rays:
// in the SortedEngine's per-leaf stage (one iteration or several), with rays traced alone, with no
// rays at all, and in the engines without a per-leaf stage (caching, Embree). Leaves no ray
// reaches get their run too; empty slots and a batch without a runner run nothing.
#include <algorithm>
#include <map>
#include <mutex>
#include <gtest/gtest.h>
#include "core/leaf_queries.h"
#include "core/parallel.h"
#include "core/rng.h"
#include "rays/caching_engine.h"
#include "rays/embree_engine.h"
#include "rays/teapot_on_floor.h"
#include "rays/sorted_engine.h"

namespace rayes {
namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kLod = 3;

struct World : test::TracedWorld {
  World() : TracedWorld(test::teapotOnFloor()) {}
};

// Records every call; concurrent runs of distinct leaves are allowed, so it locks.
class RecordingRunner final : public LeafQueryRunner {
 public:
  void run(uint32_t leaf, std::span<const uint32_t> ids) override {
    std::lock_guard lock(mutex_);
    calls.emplace_back(leaf, std::vector<uint32_t>(ids.begin(), ids.end()));
  }
  std::vector<std::pair<uint32_t, std::vector<uint32_t>>> calls;

 private:
  std::mutex mutex_;
};

// n rays from a circle around the teapot toward it (none when n = 0), slots of every third
// query empty, the others on leaf (7 q) mod leaves, so every leaf has queries and most leaves
// of the teapot are reached by few or no rays (leaves = 1: all on leaf 0).
struct Batch {
  RayBatch rays;
  LeafQueries queries;
  RecordingRunner runner;
  Batch(int n, size_t queryCount, size_t leaves) {
    rays.resize(size_t(n));
    for (int i = 0; i < n; ++i) {
      const RngKey k{uint32_t(i), 0, 0, 5};
      const float a = 6.2831853f * sampleUniform(k, 0);
      const Vec3 o{7 * std::cos(a), 7 * std::sin(a), 1 + 3 * sampleUniform(k, 1)};
      rays.setFromNowhere(size_t(i), RayKind::Closest, o, normalize(Vec3{0, 0, 1} - o), kInf, 0.0f, 0.0f);
    }
    for (size_t q = 0; q < queryCount; ++q) queries.leaf.push_back(q % 3 == 2 ? kNoLeaf : uint32_t(7 * q % leaves));
    queries.runner = &runner;
    rays.queries = &queries;
  }
};

void expectEveryQueryRunOnceOnItsLeaf(const Batch& b) {
  std::map<uint32_t, std::vector<uint32_t>> expected;
  for (uint32_t q = 0; q < b.queries.leaf.size(); ++q)
    if (b.queries.leaf[q] != kNoLeaf) expected[b.queries.leaf[q]].push_back(q);
  std::map<uint32_t, std::vector<uint32_t>> got;
  for (const auto& [leaf, ids] : b.runner.calls) {
    EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    got[leaf].insert(got[leaf].end(), ids.begin(), ids.end());
  }
  for (auto& [leaf, ids] : got) std::sort(ids.begin(), ids.end());  // chunks of a leaf in any order
  EXPECT_EQ(got, expected);  // so no slot twice, none missing, none on another leaf
}

template <class Engine>
void traceWith(Engine& engine, Batch& b) {
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b.rays, stats, times);
}

void expectTracerRunsEveryQueryOnce(int rays, size_t capacity, bool sorted, int threads, size_t queries = 500,
                                    bool oneLeaf = false) {
  ThreadLimit limit(threads);
  World w;
  TraceSettings s;
  s.maxLod = kLod;
  s.candidateCapacity = capacity;
  s.sortByLeaf = sorted;
  SortedEngine engine(w.top, w.source, s);
  Batch b(rays, queries, oneLeaf ? 1 : w.leaves.size());
  GenerationStats stats;
  TraceTimes times;
  engine.trace(b.rays, stats, times);
  expectEveryQueryRunOnceOnItsLeaf(b);
  if (sorted && rays > 0 && capacity < size_t(rays) * 8) {
    EXPECT_GT(stats.iterations.size(), 1u);  // queries ran in the first iteration only
  }
  if (oneLeaf) {
    EXPECT_GT(b.runner.calls.size(), 1u);  // chunks
  }
  // The engine leaves the slots as they were: the poster empties them.
  EXPECT_EQ(size_t(std::count(b.queries.leaf.begin(), b.queries.leaf.end(), kNoLeaf)), queries / 3);
}

TEST(LeafQueries, TracerRunsEachLeafsQueriesOnceInItsPerLeafStage) {
  for (int threads : {1, 2}) {
    expectTracerRunsEveryQueryOnce(400, 1 << 14, true, threads);
    expectTracerRunsEveryQueryOnce(400, 500, true, threads);  // several iterations
  }
}

TEST(LeafQueries, ALeafWithManyQueriesRunsThemInChunks) {
  const size_t many = 3 * (2 * LeafQueryRuns::kChunk + 1);
  expectTracerRunsEveryQueryOnce(400, 1 << 14, true, 2, many, true);
  expectTracerRunsEveryQueryOnce(0, 1 << 14, true, 2, many, true);
}

TEST(LeafQueries, RunWithoutRaysAndWithRaysTracedAlone) {
  expectTracerRunsEveryQueryOnce(0, 1 << 14, true, 2);
  expectTracerRunsEveryQueryOnce(100, 1 << 14, false, 2);
}

TEST(LeafQueries, EnginesWithoutAPerLeafStageRunThemInALoop) {
  World w;
  TraceSettings s;
  s.maxLod = kLod;
  CachingEngine caching(w.top, w.source, s, 8);
  Batch a(200, 300, w.leaves.size());
  traceWith(caching, a);
  expectEveryQueryRunOnceOnItsLeaf(a);
  EmbreeSettings es;
  es.maxLod = kLod;
  EmbreeEngine embree(w.source, es);
  Batch b(200, 300, w.leaves.size());
  traceWith(embree, b);
  expectEveryQueryRunOnceOnItsLeaf(b);
}

TEST(LeafQueries, NothingRunsWithoutARunnerOrFilledSlots) {
  World w;
  TraceSettings s;
  s.maxLod = kLod;
  SortedEngine engine(w.top, w.source, s);
  Batch b(50, 40, w.leaves.size());
  b.queries.runner = nullptr;
  EXPECT_FALSE(b.queries.pending());
  traceWith(engine, b);
  b.queries.runner = &b.runner;
  EXPECT_TRUE(b.queries.pending());
  std::fill(b.queries.leaf.begin(), b.queries.leaf.end(), kNoLeaf);
  EXPECT_FALSE(b.queries.pending());
  traceWith(engine, b);
  EXPECT_TRUE(b.runner.calls.empty());
}

}  // namespace
}  // namespace rayes
