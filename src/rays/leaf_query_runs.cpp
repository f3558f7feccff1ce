#include "rays/leaf_query_runs.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace rayes {

size_t LeafQueryRuns::group(const LeafQueries& queries) {
  clear();
  if (!queries.runner) return 0;
  std::vector<uint32_t>& filled = sort_.order;
  for (uint32_t q = 0; q < queries.leaf.size(); ++q)
    if (queries.leaf[q] != kNoLeaf) filled.push_back(q);
  if (filled.empty()) return 0;
  runner_ = queries.runner;
  leaf_ = queries.leaf;
  scratch_.resize(filled.size());
  sort_.sort(queries.leaf, scratch_);
  return runs();
}

void LeafQueryRuns::run(size_t r, TimeAccumulator& time) const {
  const std::span<const uint32_t> all = ids(r);
  auto runChunk = [&](size_t k0, size_t k1) {
    ScopedTimer timer(time);
    runner_->run(leafOf(r), all.subspan(k0, k1 - k0));
  };
  if (all.size() <= 2 * kChunk) {
    runChunk(0, all.size());
    return;
  }
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, all.size(), kChunk),
                      [&](const auto& c) { runChunk(c.begin(), c.end()); });
  });
}

void LeafQueryRuns::runAll(TimeAccumulator& time) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, runs(), 1), [&](const auto& r) {
    for (size_t run = r.begin(); run != r.end(); ++run) this->run(run, time);
  });
  clear();
}

void LeafQueryRuns::clear() {
  sort_.order.clear();
  sort_.runs.clear();
  sort_.sorted = sort_.spare = {};
  runner_ = nullptr;
  leaf_ = {};
}

}  // namespace rayes
