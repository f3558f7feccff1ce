#include "rays/leaf_query_runs.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayes {

size_t LeafQueryRuns::group(const LeafQueries& queries) {
  clear();
  if (!queries.runner) return 0;
  for (uint32_t q = 0; q < queries.leaf.size(); ++q)
    if (queries.leaf[q] != kNoLeaf) filled_.push_back(q);
  if (filled_.empty()) return 0;
  runner_ = queries.runner;
  leaf_ = queries.leaf;
  sort_.sort(filled_, queries.leaf);
  return runs();
}

void LeafQueryRuns::run(size_t r, TimeAccumulator& time) const {
  ScopedTimer timer(time);
  runner_->run(leafOf(r), ids(r));
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
  filled_.clear();
  runner_ = nullptr;
  leaf_ = {};
}

}  // namespace rayes
